"""The `calibrate` run: fit a surface to FTFOF Table I with the robot's baselines
(:mod:`ftfof.identify.calibration` says what may be fitted or held, in what bounds), and the
report of the fit: where it sits on a bound or cap, and what it does to the film."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ftfof.config import FootMechanics, Params, Surface
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
    """Fit strength and fracture energy (and ``third``, and a plate foot's backing modulus) with
    the Table I baselines; the report (:func:`ftfof.sim.calibrate.surface_fit`)."""
    from ftfof.sim.calibrate import TABLE_I, fit_start, surface_fit, with_foot

    fixed = fixed or {}
    ctx = context_of(params)
    selected = params.selected_surface
    fitted, start, robot = fit_start(ctx.name, ctx.robot, selected, third, fixed, bounds or {})
    trajectories = baseline_trajectories(params, ctx)

    def specs_for(surface: Surface, trial: FootMechanics):
        on = replace(bench(params, ctx, surface), robot=with_foot(robot, trial))
        return baseline_specs(on, trajectories, TABLE_I)

    held = f"; holding {', '.join(f'{k} = {v:g}' for k, v in fixed.items())}" if fixed else ""
    console.print(
        f"calibrating surface {params.surface!r} on {ctx.name}: fitting {', '.join(fitted)}{held}"
    )
    workers = params.acquire.workers
    report = surface_fit(robot, start, specs_for, fitted, fixed, workers, evaluations)
    return {
        "surface": params.surface,
        "robot": ctx.name,
        "foot": robot.platform.foot.model,
        **report,
        "baselines": params.baselines.model_dump(),
    }
