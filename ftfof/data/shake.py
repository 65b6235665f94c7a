"""Did the step shake the body harder than the robot allows? One verdict for the simulator
check and the report.

The peak counts over the whole step: the detachment's release (``fsj`` reads that window) and
the landing's impact alike, which no objective sees. Left to RHS alone, one seed's optimum
jittered little in detachment and hit the body on landing 2.6 times as hard as the polynomial
(measured with the mixed solver steps of the time, not checked again since).

The limit is relative to this platform, not a g-level of the real robot: the platform's body
(0.5 kg on 50 Hz mounts) accelerates 20-100 times less than the paper's IMU reads (docs/
simulator.md). MST-M3F's 3.4 m/s² is our choice, about 1.2 times the polynomial's whole-step
peak here (2.82 m/s²; paper_optimum 2.93): a step may shake the body a little more than the
common trajectory does, not several times as much.
"""

from __future__ import annotations


def shake_fault(peak_body_acc: float, limit: float | None) -> str:
    """ "" when the body's peak acceleration over the step is within the robot's ``limit``
    (m/s², or nothing is required), else what went wrong (for a message)."""
    if limit is None or peak_body_acc <= limit:
        return ""
    return f"the body shook {peak_body_acc:.1f} m/s², above the robot's {limit:.2f} m/s² limit"
