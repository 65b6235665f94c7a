"""Could a real foot run this simulated step? The rules that the simulator check refuses a
trajectory by and that the report judges the front by, in one place: the pad lets go cleanly
(:mod:`ftfof.data.release`), the film is not bent below its limit, the foot lands pressing as it
should (:mod:`ftfof.data.landing`), the landed pad holds the proof pull where the robot asks it
to (:mod:`ftfof.sim.proof`) and the body is not shaken past the robot's limit
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
    hold: str
    shake: str
    held_press: float

    @property
    def clean(self) -> bool:
        return not self.first

    @property
    def first(self) -> str:
        return self.release or self.film or self.landing or self.hold or self.shake


def foot_faults(
    t: NDArray[np.float64],
    bonds: NDArray[np.float64],
    Fp: NDArray[np.float64],
    scalars: Mapping[str, float],
    rules: FootRules,
) -> Faults:
    """The step's faults from its channels (time, bonds, pre-pressure) and its acquisition
    scalars (switch_time, max_clearance, min_bend_radius, landing_pre_pressure, held_pull,
    peak_body_acc)."""
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
    hold = hold_fault(
        scalars.get("proof_held", float("nan")),
        scalars.get("held_pull", float("nan")),
        rules.proof_pull,
    )
    shook = shake_fault(scalars["peak_body_acc"], rules.body_acc_limit)
    return Faults(release, film, landed, hold, shook, held)


def hold_fault(held: float, held_pull: float, proof_pull: float | None) -> str:
    """ "" when the landed pad ``held`` (1) ``proof_pull`` (N; None: the robot's rules ask for
    none) through the proof hold, else the most it bore."""
    if proof_pull is None or held == 1.0:
        return ""
    if held != held:
        return "the landed pad's proof pull was not measured"
    if held_pull >= proof_pull:
        return f"the landed pad bore F_proof {proof_pull:.2f} N, then let a tenth go in the hold"
    return f"the landed pad let a tenth go at {held_pull:.2f} N, below F_proof {proof_pull:.2f} N"
