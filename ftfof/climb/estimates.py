"""What the controller's estimator made of each slip against the sliding pad's truth (issue 51).

Each slip the controller declared (:class:`~ftfof.climb.control.state.SlipEstimate`: every
controller fits the slipping pad, only ``replan`` and ``both`` believe it) is set beside the
truth a slip test at the pad's speed would recover on the preset the pad stands on then (the
surface change's from its time on): mu and F_adh(v) = R(v) F_adh,0, ``identify``'s own
definition (:func:`ftfof.sim.identified.truth`), at the median slip speed over the estimator's
window. Both in the slip law's tangential form, F_adh in newtons of shear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.feedforward import ESTIMATE_SAMPLES
from ftfof.climb.control.state import SlipEstimate
from ftfof.climb.model import ClimbSpec
from ftfof.climb.surface import surface_at
from ftfof.config import LEG_NAMES
from ftfof.identify.estimate import Estimate
from ftfof.sim.bonds import BondLaw
from ftfof.sim.identified import truth

Array = NDArray[np.float64]


@dataclass(frozen=True)
class SlipEpisode:
    """One slip: the estimator's fit beside the pad's truth at the slip's speed."""

    time: float  # s: the slip's declaration
    foot: int
    speed: float  # m/s: the pad's median slip speed over the estimator's window
    estimate: Estimate
    truth: Estimate

    @property
    def errors(self) -> tuple[float, float]:
        """|estimate / truth - 1| of mu and of F_adh."""
        return (
            abs(self.estimate.mu / self.truth.mu - 1.0),
            abs(self.estimate.adhesion / self.truth.adhesion - 1.0),
        )

    def row(self) -> dict[str, Any]:
        """The slip as its climb's JSON keeps it (a non-finite number as null)."""
        mu, adhesion = self.errors
        est, true = self.estimate, self.truth
        return {
            "time": self.time,
            "foot": LEG_NAMES[self.foot],
            "speed": self.speed,
            "mu": {"estimate": _json(est.mu), "truth": true.mu, "error": _json(mu)},
            "adhesion": {
                "estimate": _json(est.adhesion),
                "truth": true.adhesion,
                "error": _json(adhesion),
            },
        }


def _json(value: float) -> float | None:
    return value if math.isfinite(value) else None


def pad_truth(spec: ClimbSpec, foot: int, time: float, speed: float) -> Estimate:
    """mu and F_adh(v) of ``foot``'s pad at ``time`` slid at ``speed`` (m/s): the preset it
    stands on then (:func:`~ftfof.climb.surface.surface_at`), pressed at the robot's
    pre-pressure, as :func:`ftfof.sim.identified.truth` defines them."""
    surface = surface_at(spec.switch, spec.surface, foot, time)
    law = BondLaw.from_surface(surface, spec.solver.contact_smoothing)
    return truth(law, spec.robot, speed)


def slip_speed(t: Array, slip_velocity: Array, foot: int, time: float) -> float:
    """``foot``'s median |slip velocity| over the last ESTIMATE_SAMPLES records up to ``time``,
    the records its estimate was fitted from."""
    upto = int(np.searchsorted(t, time + 1e-9))
    window = slip_velocity[max(upto - ESTIMATE_SAMPLES, 0) : upto, foot]
    return float(np.median(np.abs(window))) if window.size else 0.0


def episodes(
    spec: ClimbSpec, channels: dict[str, Array], estimates: list[SlipEstimate]
) -> list[SlipEpisode]:
    """Each of a climb's ``estimates`` beside its pad's truth, from the climb's ``channels``."""
    out = []
    for e in estimates:
        speed = slip_speed(channels["t"], channels["slip_velocity"], e.foot, e.time)
        true = pad_truth(spec, e.foot, e.time, speed)
        out.append(SlipEpisode(e.time, e.foot, speed, e.fit, true))
    return out


def estimate_summary(slips: list[SlipEpisode]) -> dict[str, float]:
    """The median relative error of mu and of F_adh over the slips (nan without any), and how
    many slips were estimated."""
    errors = np.array([s.errors for s in slips]).reshape(-1, 2)
    median = np.median(errors, axis=0) if len(slips) else (math.nan, math.nan)
    return {
        "mu_error": float(median[0]),
        "adhesion_error": float(median[1]),
        "estimated_slips": float(len(slips)),
    }
