"""Did a simulated foot land pressing as it should? One verdict for the simulator check and the
report.

The pre-pressure a is what the pad needs to bond on the next stance (the bond law's preload
factor 1 - exp(-p / p*)); a landing that presses far less bonds weaker, and one that presses far
more loads the leg. The robot's ``landing_tolerance`` says how far the landing press may miss a.
"""

from __future__ import annotations


def landing_fault(pressed: float, target: float, tolerance: float | None) -> str:
    """ "" when the landing press is within ``tolerance`` x a of a (or nothing is required),
    else what went wrong (for a message)."""
    if tolerance is None or abs(pressed - target) <= tolerance * target:
        return ""
    return (
        f"the landing pressed {pressed:.2f} N, outside a = {target:.2f} N ± {100 * tolerance:.0f} %"
    )
