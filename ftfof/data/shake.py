"""Did the step shake the body harder than the robot allows? One verdict for the simulator
check and the report.

The peak counts over the whole step: the detachment's snap (``fsj`` reads that window) and the
landing's impact alike, which no objective sees. Left to RHS alone, one seed's optimum jittered
little in detachment and hit the body at 21 m/s² on landing, 2.6 times the polynomial's.

The limit is relative to this platform, not a g-level of the real robot: the platform's body
(0.5 kg on 50 Hz mounts) accelerates 10-30 times less than the paper's IMU reads (docs/
simulator.md). MST-M3F's 9.81 m/s² is our choice, about 1.2 times the polynomial's whole-step
peak here (8.2 m/s²; paper_optimum 11.1): a step may shake the body a little more than the
common trajectory does, not several times as much.
"""

from __future__ import annotations


def shake_fault(peak_body_acc: float, limit: float | None) -> str:
    """ "" when the body's peak acceleration over the step is within the robot's ``limit``
    (m/s², or nothing is required), else what went wrong (for a message)."""
    if limit is None or peak_body_acc <= limit:
        return ""
    return f"the body shook {peak_body_acc:.1f} m/s², above the robot's {limit:.2f} m/s² limit"
