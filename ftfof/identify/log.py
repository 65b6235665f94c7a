"""A slip test's record, as the simulator writes it and a physical platform's log is read."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]
COLUMNS = ("t", "Fx", "Fz", "load")


@dataclass(frozen=True)
class SlipLog:
    """Sensor samples of a slip test, the loads one after the other on one time axis."""

    t: Array  # s, increasing
    Fx: Array  # N, tangential, drag direction positive
    Fz: Array  # N, normal, tension positive
    load: Array  # the commanded normal load of the sample's run, N, compression positive

    def columns(self) -> dict[str, Array]:
        return {name: getattr(self, name) for name in COLUMNS}


def slip_samples(log: SlipLog, band: float = 0.01) -> NDArray[np.bool_]:
    """The samples at the friction limit: in each load's run, those up to its peak tangential
    force whose force is within ``band`` of that peak (the bonds letting go). The peak is broad
    (the bonds soften over their opening while friction holds mu F_n), and samples a few
    per cent below it lie on its rising flank, still elastic: the band is 1 %. After the peak
    the pad slides on broken bonds, which the law F_t = mu F_n + F_adh does not describe, so
    those are left out."""
    keep = np.zeros(log.t.size, dtype=bool)
    starts = np.flatnonzero(np.r_[True, np.diff(log.load) != 0])
    for a, b in zip(starts, np.r_[starts[1:], log.t.size], strict=True):
        ft = np.abs(log.Fx[a:b])
        peak = int(np.argmax(ft))
        keep[a : a + peak + 1] = ft[: peak + 1] >= (1 - band) * ft[peak]
    return keep
