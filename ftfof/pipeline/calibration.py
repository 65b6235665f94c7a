"""Fitting a surface to FTFOF Table I: which parameters may be fitted or fixed, within what bounds,
and the report of a fit: where it sits on a bound or cap, and what it does to the film."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

from ftfof.config import Params, Surface
from ftfof.errors import ParamsError
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench, context_of
from ftfof.pipeline.console import console
from ftfof.sim import film

BOUNDS = {"strength": (2e3, 5e5), "fracture_energy": (1.0, 5e3)}
THIRD_BOUNDS = {
    "preload_pressure": (2e2, 5e4),
    "rate_exponent": (0.1, 1.2),
    "rate_speed": (1e-3, 1.0),
    "shear_energy_ratio": (0.1, 10.0),
    "friction": (0.1, 1.5),
    "contact_stiffness": (1e7, 1e10),
}
FITTABLE = {**BOUNDS, **THIRD_BOUNDS}


def _pair(option: str, text: str) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    key = key.strip()
    if not sep or not value.strip():
        raise ParamsError(option, f"{text!r} is not key=value")
    if key not in FITTABLE:
        raise ParamsError(
            f"{option} {key}", f"is not a surface parameter the fit knows ({', '.join(FITTABLE)})"
        )
    return key, value.strip()


def _number(option: str, key: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ParamsError(f"{option} {key}", f"{text!r} is not a number") from None
    if not math.isfinite(value) or value <= 0:
        raise ParamsError(f"{option} {key}", f"must be a positive number (got {text})")
    return value


def parse_fixes(texts: Iterable[str]) -> dict[str, float]:
    """``--fix key=value``: surface values held, not fitted."""
    out: dict[str, float] = {}
    for text in texts:
        key, value = _pair("--fix", text)
        if key in out:
            raise ParamsError(f"--fix {key}", "is given twice")
        out[key] = _number("--fix", key, value)
    return out


def parse_bounds(texts: Iterable[str]) -> dict[str, tuple[float, float]]:
    """``--bound key=lo:hi``: the range a fitted value may take."""
    out: dict[str, tuple[float, float]] = {}
    for text in texts:
        key, value = _pair("--bound", text)
        if key in out:
            raise ParamsError(f"--bound {key}", "is given twice")
        lo_text, sep, hi_text = value.partition(":")
        if not sep:
            raise ParamsError(f"--bound {key}", f"{value!r} is not lo:hi")
        lo, hi = _number("--bound", key, lo_text), _number("--bound", key, hi_text)
        if not lo < hi:
            raise ParamsError(f"--bound {key}", f"needs lo < hi (got {value})")
        out[key] = (lo, hi)
    return out


def fit_bounds(
    third: str | None, fixed: dict[str, float], overrides: dict[str, tuple[float, float]]
) -> dict[str, tuple[float, float]]:
    """The fitted parameters and their ranges: strength and G unless fixed, plus ``third``."""
    bounds = {k: v for k, v in BOUNDS.items() if k not in fixed}
    if third and third != "none":
        if third not in THIRD_BOUNDS:
            raise ParamsError(
                "--third", f"cannot fit {third!r} (choose from {', '.join(THIRD_BOUNDS)})"
            )
        if third not in fixed:
            bounds[third] = THIRD_BOUNDS[third]
    for key, pair in overrides.items():
        if key in fixed:
            raise ParamsError(f"--bound {key}", "is also fixed by --fix: bound it or fix it")
        if key not in bounds:
            raise ParamsError(f"--bound {key}", f"is not fitted (fitted: {', '.join(bounds)})")
        bounds[key] = pair
    if not bounds:
        raise ParamsError("--fix", "holds every parameter: nothing is left to fit")
    return bounds


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
