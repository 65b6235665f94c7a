"""The `calibrate` run: fit a surface to FTFOF Table I with the robot's baselines
(:mod:`ftfof.identify.calibration` says what may be fitted or held, in what bounds), and the
report of the fit: where it sits on a bound or cap, and what it does to the film."""

from __future__ import annotations

from typing import Any

from ftfof.config import Params, Surface
from ftfof.identify.calibration import fit_bounds
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench, context_of
from ftfof.pipeline.console import console
from ftfof.sim import film


def fit_surface(
    params: Params,
    third: str | None,
    evaluations: int,
    fixed: dict[str, float] | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
) -> dict[str, Any]:
    """Fit strength and fracture energy (and ``third``) with the Table I baselines; the report."""
    from ftfof.sim.calibrate import TABLE_I, calibrate, film_report

    fixed = fixed or {}
    ctx = context_of(params)
    fitted = fit_bounds(third, fixed, bounds or {})
    start = params.selected_surface.model_copy(update=fixed)
    trajectories = baseline_trajectories(params, ctx)
    f = ctx.robot.platform.film
    cap = film.survival_energy(f.bending_stiffness, f.width, ctx.robot.foot.film_min_bend_radius)

    def specs_for(surface: Surface):
        return baseline_specs(bench(params, ctx, surface), trajectories, TABLE_I)

    held = f"; holding {', '.join(f'{k} = {v:g}' for k, v in fixed.items())}" if fixed else ""
    console.print(
        f"calibrating surface {params.surface!r} on {ctx.name}: fitting {', '.join(fitted)}{held}"
    )
    fit = calibrate(start, specs_for, fitted, params.acquire.workers, evaluations, cap)
    surface = start.model_copy(update=fit.values)
    active = dict(fit.active)
    if fixed.get("fracture_energy", 0.0) > cap:  # held there by hand: the report says so
        active["fracture_energy"] = "fixed above the fracture-energy cap"
    return {
        "surface": params.surface,
        "robot": ctx.name,
        "targets": TABLE_I,
        "values": fit.values,
        "fixed": fixed,
        "bounds": {k: list(v) for k, v in fitted.items()},
        "fracture_energy_cap": cap,
        "active": active,
        "residuals": fit.residuals,
        "measured": fit.measured,
        "worst_relative_error": fit.worst,
        "film": film_report(ctx.robot, surface, fit.measured),
        "evaluations": fit.evaluations,
        "history": fit.history,
        "baselines": params.baselines.model_dump(),
    }
