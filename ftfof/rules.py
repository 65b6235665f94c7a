"""A robot's limits on one step, in one place: what a real foot must survive. Built once per robot
context (:func:`ftfof.robot.robot_context`) and read by the search's constraints on what the
surrogate predicts (:mod:`ftfof.optimize.problem`), by the simulator check and by the report
(:mod:`ftfof.data.faults`)."""

from __future__ import annotations

from dataclasses import dataclass

from ftfof.config import Protocol, Robot, Surface
from ftfof.demand import proof_pull
from ftfof.sim.film import FilmLimit, film_limit


@dataclass(frozen=True)
class FootRules:
    """A robot's limits on one simulated step (SI units)."""

    film: FilmLimit  # the least bend radius the film may take (fc), with the peel-root diagnostic
    swing_clearance: float  # how far the whole pad must rise above the wall
    detached: float  # the protocol's switch height: above it the pad counts as off the wall
    landing_start: float  # T2: the pad must stay off the wall from the switch until then
    pre_pressure: float  # a
    landing_tolerance: float | None  # fraction of a the landing press may miss it by
    retouch_allowed: float | None  # bonds the pad may re-form before the landing (None: any)
    landing_hold: float  # how long the protocol holds the landing press
    body_acc_limit: float | None  # the body's peak acceleration over the step
    # F_proof the landed pad must hold (ftfof/sim/proof.py); None: not required (no proof pull,
    # or the robot's proof.refuse off)
    proof_pull: float | None = None


def foot_rules(robot: Robot, surface: Surface, protocol: Protocol) -> FootRules:
    """``robot``'s rules on ``surface`` under the acquisition ``protocol``."""
    return FootRules(
        film=film_limit(robot, surface),
        swing_clearance=robot.foot.swing_clearance,
        detached=protocol.switch_height,
        landing_start=robot.timing.T2,
        pre_pressure=robot.pre_pressure,
        landing_tolerance=robot.landing_tolerance,
        retouch_allowed=robot.retouch_allowed,
        landing_hold=protocol.landing_hold,
        body_acc_limit=robot.body_acc_limit,
        proof_pull=proof_pull(robot) if robot.proof is not None and robot.proof.refuse else None,
    )
