"""Fitting a surface to FTFOF Table I: which parameters may be fitted, within what bounds, and the
report of a fit."""

from __future__ import annotations

from typing import Any

from ftfof.config import Params, Surface
from ftfof.errors import ParamsError
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench
from ftfof.pipeline.console import console
from ftfof.robot import robot_context

THIRD_BOUNDS = {
    "preload_pressure": (2e2, 5e4),
    "rate_exponent": (0.1, 1.2),
    "rate_speed": (1e-3, 1.0),
    "shear_energy_ratio": (0.1, 10.0),
    "friction": (0.1, 1.5),
    "contact_stiffness": (1e7, 1e10),
}
BOUNDS = {"strength": (2e3, 5e5), "fracture_energy": (1.0, 5e3)}


def fit_surface(params: Params, third: str | None, evaluations: int) -> dict[str, Any]:
    """Fit strength and fracture energy (and ``third``) with the Table I baselines; the report."""
    from ftfof.sim.calibrate import TABLE_I, calibrate

    ctx = robot_context(params)
    bounds = dict(BOUNDS)
    if third and third != "none":
        if third not in THIRD_BOUNDS:
            raise ParamsError(
                "--third", f"cannot fit {third!r} (choose from {', '.join(THIRD_BOUNDS)})"
            )
        bounds[third] = THIRD_BOUNDS[third]
    trajectories = baseline_trajectories(params, ctx)

    def specs_for(surface: Surface):
        return baseline_specs(bench(params, ctx, surface), trajectories, TABLE_I)

    console.print(
        f"calibrating surface {params.surface!r} on {ctx.name}: fitting {', '.join(bounds)}"
    )
    fit = calibrate(params.selected_surface, specs_for, bounds, params.acquire.workers, evaluations)
    return {
        "surface": params.surface,
        "robot": ctx.name,
        "targets": TABLE_I,
        "values": fit.values,
        "residuals": fit.residuals,
        "measured": fit.measured,
        "worst_relative_error": fit.worst,
        "evaluations": fit.evaluations,
        "history": fit.history,
        "baselines": params.baselines.model_dump(),
    }
