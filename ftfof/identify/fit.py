"""A slip log's friction and adhesion: the estimators on the samples where the pad lets go, the
report of them and the surface preset they give."""

from __future__ import annotations

from typing import Any

import numpy as np

from ftfof.config import Surface
from ftfof.errors import ParamsError
from ftfof.identify.estimate import Estimate, Track, kalman, least_squares
from ftfof.identify.log import SlipLog, slip_samples


def identify(log: SlipLog) -> tuple[Estimate, Track]:
    """Least squares over the slip samples, and the Kalman estimate started from it (the seed's
    filter needs a start near the truth: a window holds one load, so the first windows alone
    cannot give one)."""
    slip = slip_samples(log)
    fn, ft = -log.Fz[slip], np.abs(log.Fx[slip])
    ls = least_squares(fn, ft)
    return ls, kalman(fn, ft, ls)


def report(
    name: str, source: str, ls: Estimate, track: Track, true: Estimate | None
) -> dict[str, Any]:
    def block(key: str) -> dict[str, float | None]:
        return {
            "estimate": getattr(track.final, key),
            "truth": getattr(true, key) if true else None,
            "least_squares": getattr(ls, key),
        }

    return {
        "enabled": True,
        "surface": name,
        "source": source,
        "slip_samples": int(track.samples[-1]),
        "mu": block("mu"),
        "adhesion": block("adhesion"),
        "adhesion_unit": "N per pad, of shear: F_t = mu F_n + F_adh",
    }


def parse_speeds(text: str) -> list[float]:
    """``--speeds v1,v2``: two distinct positive drag speeds, m/s."""
    try:
        speeds = [float(v) for v in text.split(",")]
    except ValueError:
        raise ParamsError("--speeds", f"{text!r} is not two numbers, v1,v2 (m/s)") from None
    if len(speeds) != 2 or min(speeds) <= 0 or speeds[0] == speeds[1]:
        raise ParamsError("--speeds", f"needs two distinct positive speeds, got {text!r}")
    return speeds


def preset_block(
    surface: Surface, source: str, mu: float, tau: float, pull_off: float | None = None
) -> dict[str, Any]:
    """``surface``'s preset with the identified friction ``mu`` and shear strength ``tau``
    (tau_max, Pa). Without a peel calibration the pull-off strength follows from tau through the
    preset's k = tau / sigma; with one (``pull_off``: sigma fitted on normal peel data) k follows
    from both."""
    block = surface.model_dump()
    block["friction"] = round(mu, 4)
    block["note"] = f"{surface.note} Friction and shear identified by ftfof identify ({source})."
    if pull_off is None:
        block["strength"] = round(tau / surface.shear_capacity_ratio, 1)
    else:
        block["strength"] = round(pull_off, 1)
        block["shear_capacity_ratio"] = round(tau / pull_off, 4)
        block["shear_source"] = "ftfof identify: slip-test shear over ftfof calibrate's pull-off"
    return block
