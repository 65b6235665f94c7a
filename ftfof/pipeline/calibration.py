"""The `calibrate` run: fit a surface to FTFOF Table I with the robot's baselines
(:mod:`ftfof.identify.calibration` says what may be fitted or held, in what bounds), and the
report of the fit: where it sits on a bound or cap, and what it does to the film."""

from __future__ import annotations

from typing import Any

from ftfof.config import Params, Surface
from ftfof.identify.calibration import fit_bounds
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.console import console
from ftfof.sim.spec import baseline_specs


def fit_surface(
    params: Params,
    third: str | None,
    evaluations: int,
    fixed: dict[str, float] | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
) -> dict[str, Any]:
    """Fit strength and fracture energy (and ``third``) with the Table I baselines; the report
    (:func:`ftfof.sim.calibrate.surface_fit`)."""
    from ftfof.sim.calibrate import TABLE_I, surface_fit

    fixed = fixed or {}
    ctx = context_of(params)
    fitted = fit_bounds(third, fixed, bounds or {})
    start = params.selected_surface.model_copy(update=fixed)
    trajectories = baseline_trajectories(params, ctx)

    def specs_for(surface: Surface):
        return baseline_specs(bench(params, ctx, surface), trajectories, TABLE_I)

    held = f"; holding {', '.join(f'{k} = {v:g}' for k, v in fixed.items())}" if fixed else ""
    console.print(
        f"calibrating surface {params.surface!r} on {ctx.name}: fitting {', '.join(fitted)}{held}"
    )
    workers = params.acquire.workers
    report = surface_fit(ctx.robot, start, specs_for, fitted, fixed, workers, evaluations)
    return {
        "surface": params.surface,
        "robot": ctx.name,
        **report,
        "baselines": params.baselines.model_dump(),
    }
