"""Did a simulated pad let go cleanly? One verdict for the simulator check and the report.

A pad lets go cleanly when the photoelectric switch trips (every bond broken, the film clear of
the plate), the whole pad then rises ``required`` above the wall, and nothing of it touches the
wall again before the landing segment starts at T2: a swing that re-bonds the film mid-air, or
leaves its tail on the wall, drags it while the foot still moves.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray


def swing_gap(clearance: NDArray[np.float64], t: NDArray[np.float64], required: float,
              landing_start: float) -> NDArray[np.float64]:  # fmt: skip
    """(..., n) clearance series on the times ``t`` -> (...,) the lowest the pad comes to the
    wall between first rising ``required`` above it and the landing segment; 0 if it never
    rises that far. The continuous measure of a clean release that a surrogate can predict."""
    risen = np.cumsum(clearance >= required, axis=-1) > 0
    window = risen & (t < landing_start)
    lowest = np.min(np.where(window, clearance, np.inf), axis=-1)
    return np.where(window.any(axis=-1), lowest, 0.0)


def release_fault(
    t: NDArray[np.float64],
    bonds: NDArray[np.float64],
    switch_time: float,
    max_clearance: float,
    required: float,
    landing_start: float,
) -> str:
    """ "" for a clean release, else what went wrong (for a message)."""
    if not math.isfinite(switch_time):
        return "the pad never let go"
    if not max_clearance >= required:  # NaN: no clearance measured, no clean release
        return (
            f"the pad rose only {1e3 * max_clearance:.1f} mm above the wall "
            f"(needs {1e3 * required:.1f} mm)"
        )
    swing = (t > switch_time) & (t < landing_start)
    touched = np.flatnonzero(swing & (bonds > 0))
    if touched.size:
        return f"the pad touched the wall again in the swing at t = {t[touched[0]]:.3f} s"
    return ""
