"""What a fit of a surface to FTFOF Table I (``ftfof calibrate``; the fit is
:mod:`ftfof.sim.calibrate`) may fit or hold: the parameters it knows, their default ranges, and
the ``--fix key=value`` and ``--bound key=lo:hi`` that change them, each refused by name; and
the strength a fit reports, which `identify` starts from.

The plate foot's backing modulus is fitted beside the surface within the range of the foams and
elastomers such backings are made of: 0.1-10 MPa (a soft polyurethane foam to a hard silicone;
an acrylic foam tape is about 0.5-1 MPa)."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

from ftfof.errors import DataError, ParamsError

BOUNDS = {"strength": (2e3, 5e5), "fracture_energy": (1.0, 5e3)}
THIRD_BOUNDS = {
    "preload_pressure": (2e2, 5e4),
    "rate_exponent": (0.1, 1.2),
    "rate_speed": (1e-3, 1.0),
    "shear_energy_ratio": (0.1, 10.0),
    "friction": (0.1, 1.5),
    "contact_stiffness": (1e7, 1e10),
}
BACKING_BOUNDS = {"backing_modulus": (1e5, 1e7)}
FITTABLE = {**BOUNDS, **THIRD_BOUNDS, **BACKING_BOUNDS}


def _pair(option: str, text: str) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    key = key.strip()
    if not sep or not value.strip():
        raise ParamsError(option, f"{text!r} is not key=value")
    if key not in FITTABLE:
        raise ParamsError(
            f"{option} {key}", f"is not a parameter the fit knows ({', '.join(FITTABLE)})"
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
    third: str | None,
    fixed: dict[str, float],
    overrides: dict[str, tuple[float, float]],
    backing: bool = False,
) -> dict[str, tuple[float, float]]:
    """The fitted parameters and their ranges: strength and G unless fixed, plus ``third``, plus
    the plate foot's backing modulus where ``backing``."""
    bounds = {k: v for k, v in BOUNDS.items() if k not in fixed}
    if backing:
        bounds.update({k: v for k, v in BACKING_BOUNDS.items() if k not in fixed})
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


def fitted_strength(report: Any, surface: str, where: str) -> float:
    """The pull-off strength sigma a fit's ``report`` (read from ``where``) fitted or held for
    ``surface``."""
    try:
        strength = {**report["fixed"], **report["values"]}.get("strength")
        fitted_on = report["surface"]
    except (KeyError, TypeError) as err:
        raise DataError(where, f"not a calibration report ({err})") from None
    if fitted_on != surface:
        raise DataError(where, f"calibrates surface {fitted_on!r}, not {surface!r}")
    if strength is None:
        raise DataError(where, "has no strength (fitted or fixed)")
    return float(strength)
