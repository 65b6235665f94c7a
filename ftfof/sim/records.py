"""The record of one acquisition, simulated or imported, and the names of its channels.

Kept apart from the simulator so that code reading or writing acquisitions (the acquisition
table, imported force logs) does not load Exudyn.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

CHANNELS = (
    "t",  # s, from the start of the trajectory
    "x_cmd",  # commanded foot (ankle) x, m
    "z_cmd",  # commanded foot z without the press, m
    "x_foot",  # actual ankle x, m
    "z_foot",  # actual ankle z above its rest height, m
    "Fx",  # sensor tangential reading, N (includes the plate's inertia)
    "Fz",  # sensor normal reading, + = tension (detachment), N
    "Fx_pad",  # foot force along the wall: the pad-plate interface force (bonds + contact), N
    "Fz_pad",  # foot force normal to the wall, + = tension, N
    "Fd",  # detachment force max(Fz_pad, 0), N
    "Fp",  # pre-pressure max(-Fz_pad, 0), N (starts at the initial press a)
    "body_acc",  # IMU acceleration magnitude, m/s^2
    "bonds",  # intact bonds
    "switch",  # photoelectric switch state (1 = foot detached)
    "film_curvature",  # max curvature of the film's free span (clamp to peel front), 1/m
    "film_clearance",  # height of the film's lowest point above the plate (0 while touching), m
)


class Status(StrEnum):
    """A sample's outcome; the value is what the acquisition table's ``status`` column holds."""

    OK = "ok"
    FAILED = "failed"


class FailureReason(StrEnum):
    """Why a sample failed: decides whether a second attempt can help (the message says more)."""

    SOLVER = "solver"  # the solver raised
    NON_FINITE_STATE = "non-finite state"  # the state diverged during the run
    TIME_BUDGET = "time budget"  # the run used up its wall-time budget
    STOPPED_EARLY = "stopped early"  # the solver returned before the end time
    NON_FINITE_SENSOR = "non-finite sensor"  # a resampled channel holds NaN or inf
    WORKER_CRASHED = "worker crashed"  # the process running the sample died


@dataclass
class SampleResult:
    key: str
    source: str
    sample_id: int
    status: Status
    error: str
    wall_time: float
    channels: dict[str, Array]
    scalars: dict[str, float] = field(default_factory=dict)
    reason: FailureReason | None = None  # set for a failed sample; not stored in tables

    @property
    def ok(self) -> bool:
        return self.status == Status.OK


def force_peaks(fx: Array, fz: Array, attached: NDArray[np.bool_]) -> dict[str, float]:
    """Peaks of the foot force while the pad holds (``attached``), tension positive.

    ``peak_pull`` is the resultant the foot pulls with, |(Fx, max(Fz, 0))|: it counts the pad
    sheared off under compression as well as peeled or pulled off, so that neither mode looks
    free to an optimiser. ``peak_normal`` is the tension alone, ``peak_shear`` the shear alone.
    A missing tangential channel (NaN, e.g. a 1-axis log) leaves ``peak_shear`` NaN and the pull
    normal-only.
    """
    tension = np.maximum(fz[attached], 0.0)
    shear = np.abs(fx[attached])
    has_shear = shear.size > 0 and np.isfinite(shear).all()
    pull = np.hypot(shear, tension) if has_shear else tension
    return {
        "peak_normal": float(np.max(tension, initial=0.0)),
        "peak_shear": float(np.max(shear, initial=0.0)) if has_shear else float("nan"),
        "peak_pull": float(np.max(pull, initial=0.0)),
    }
