"""What a climbing robot's stance foot must hold on the wall, from its climber preset alone.

The climbing simulation (:mod:`ftfof.climb`) builds its robot from these masses, and the platform
tests a landed pad against the same demand (the proof pull, :mod:`ftfof.sim.proof`), so both
read one formula (decision 0019).
"""

from __future__ import annotations

import ftfof.config as config

LEGS = 4  # a quadruped
SERVO_LINK_MASS = 0.005  # kg, the ankle servo's output flange


def leg_masses(robot: config.Robot) -> tuple[float, float, float]:
    """Thigh, shank and ankle flange of each leg, kg."""
    m = robot.platform.link_mass
    return m, m, SERVO_LINK_MASS


def robot_mass(robot: config.Robot) -> float:
    """The climbing robot's whole mass: trunk, four legs, four feet (films are grams)."""
    assert robot.climber is not None
    return robot.climber.trunk_mass + LEGS * (sum(leg_masses(robot)) + robot.platform.foot.mass)


def fore_foot_demand(robot: config.Robot) -> float:
    """The pull a fore stance foot holds while the other fore foot presses its landing, N:
    a + m g h / L. On a wall the feet's normal forces sum to zero, so a fore landing's press a
    pulls on its partner, and the trunk's weight m g, its hips h off the wall, tips the robot
    about its hind feet L below (decision 0019)."""
    assert robot.climber is not None
    h = robot.leg.hip.z
    return robot.pre_pressure + robot_mass(robot) * config.GRAVITY * h / robot.climber.hip_spacing


# the proof test's lines, one home for the simulated platform and an imported log's pull
LET_GO = 0.1  # the share of the landed pad whose loss ends the test: it did not hold
REACHED = 0.98  # of F_proof: the sensor read the pull (the loop settles in 10 ms of a 0.5 s hold)


def proof_pull(robot: config.Robot) -> float | None:
    """F_proof, N: the fore foot's demand times the robot's ``proof.safety_factor``; None where
    the robot asks for no proof pull."""
    if robot.proof is None:
        return None
    return robot.proof.safety_factor * fore_foot_demand(robot)
