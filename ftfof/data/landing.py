"""Did a simulated foot land pressing as it should? One verdict for the simulator check and the
report.

The pre-pressure a is what the pad needs to bond on the next stance (the bond law's preload
factor 1 - exp(-p / p*)); a landing that presses far less bonds weaker, and one that presses far
more loads the leg. The robot's ``landing_tolerance`` says how far the landing press may miss a.
Both its peak (fs3's, FTFOF eq. 12) and the press the foot still holds at the end of the landing
hold must be within it: a brief impact that touches a and then lets the press sag does not
preload the pad.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

HELD_WINDOW = 0.05  # s: the end of the landing hold over which the held press is averaged


def held_press(t: NDArray[np.float64], Fp: NDArray[np.float64], landing_hold: float) -> float:
    """The mean pre-pressure over the last :data:`HELD_WINDOW` (at most the whole landing hold)
    of a record, which ends with the hold."""
    window = t >= float(t[-1]) - min(HELD_WINDOW, landing_hold)
    return float(np.mean(Fp[window]))


def landing_fault(peak: float, held: float, target: float, tolerance: float | None) -> str:
    """ "" when the landing's peak press and its held press are both within ``tolerance`` x a of
    a (or nothing is required), else what went wrong (for a message)."""
    if tolerance is None:
        return ""
    band = f"outside a = {target:.2f} N ± {100 * tolerance:.0f} %"
    for what, value in (("pressed", peak), ("held", held)):
        if not abs(value - target) <= tolerance * target:  # NaN: no press measured
            return f"the landing {what} {value:.2f} N, {band}"
    return ""
