"""Could a real foot run this simulated step? The four rules that the simulator check refuses a
trajectory by and that the report judges the front by, in one place: the pad lets go cleanly
(:mod:`ftfof.data.release`), the film is not bent below its limit, the foot lands pressing as it
should (:mod:`ftfof.data.landing`) and the body is not shaken past the robot's limit
(:mod:`ftfof.data.shake`). A value the simulation did not give (NaN) breaks its rule.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.data.landing import held_press, landing_fault
from ftfof.data.release import release_fault
from ftfof.data.shake import shake_fault
from ftfof.rules import FootRules


@dataclass(frozen=True)
class Faults:
    """What went wrong with one step under each rule ("" for none), in the order the simulator
    check tells them, and the press the foot held at the end of the landing."""

    release: str
    film: str
    landing: str
    shake: str
    held_press: float

    @property
    def clean(self) -> bool:
        return not self.first

    @property
    def first(self) -> str:
        return self.release or self.film or self.landing or self.shake


def foot_faults(
    t: NDArray[np.float64],
    bonds: NDArray[np.float64],
    Fp: NDArray[np.float64],
    scalars: Mapping[str, float],
    rules: FootRules,
) -> Faults:
    """The step's faults from its channels (time, bonds, pre-pressure) and its acquisition
    scalars (switch_time, max_clearance, min_bend_radius, landing_pre_pressure, peak_body_acc)."""
    release = release_fault(
        t,
        bonds,
        scalars["switch_time"],
        scalars["max_clearance"],
        rules.swing_clearance,
        rules.landing_start,
    )
    bend = scalars["min_bend_radius"]
    film = (
        ""
        if bend >= rules.film.radius
        else f"film bent to {1e3 * bend:.2f} mm, below its {1e3 * rules.film.radius:.2f} mm limit"
    )
    held = held_press(t, Fp, rules.landing_hold)
    landed = landing_fault(
        scalars["landing_pre_pressure"], held, rules.pre_pressure, rules.landing_tolerance
    )
    shook = shake_fault(scalars["peak_body_acc"], rules.body_acc_limit)
    return Faults(release, film, landed, shook, held)
