"""Did the step shake the body more than the stance feet can hold? One verdict for the simulator
check and the report.

The stance feet hold the robot's weight on the wall by their bonds' shear capacity, sized with a
safety factor (surfaces' ``shear_capacity_ratio``: three feet hold the weight with factor 2). A
body acceleration a loads them with a further m a on top of m g, so a peak above (factor - 1) g
spends the whole margin. The peak counts over the whole step: the detachment's snap (``fsj``
reads that window) and the landing's impact alike, which no objective sees.
"""

from __future__ import annotations


def shake_fault(peak_body_acc: float, limit: float | None) -> str:
    """ "" when the body's peak acceleration over the step is within the robot's ``limit``
    (m/s², or nothing is required), else what went wrong (for a message)."""
    if limit is None or peak_body_acc <= limit:
        return ""
    return f"the body shook {peak_body_acc:.1f} m/s², above the robot's {limit:.2f} m/s² limit"
