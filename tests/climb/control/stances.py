"""The M3F climber's four feet on the wall as a contact-force QP's stance."""

from __future__ import annotations

import numpy as np

from ftfof.climb.control.forces import Stance
from ftfof.climb.legs import sagittal_chain

MASS = 0.8  # kg: the M3F climber's estimate (params.yaml, robots.mst_m3f.climber)
GRAVITY = 9.81
FRICTION, ADHESION = 0.6, 8.0
PULL_OFF = 8.0  # N: as F_adh, the pyramid cut at its apex
WEIGHTS = (1.0, 1e-3)  # tangential, normal: the normal weight far below (climbing_slip §5.2)
STROKE = np.array([0.02, 0.08, 0.05, 0.11])  # each foot along its stance stroke, m (FL FR HL HR)


def stance_of(m3f, stroke: np.ndarray = STROKE) -> Stance:
    """Every foot on the wall at ``stroke`` from its P0, the body level, the CoM midway between
    the hips at their height."""
    robot = m3f.robot
    chain = sagittal_chain(robot.leg, robot.climber.torque_limits, robot.platform.foot.ankle_height)
    spacing = robot.climber.hip_spacing
    hips = np.array([spacing, spacing, -spacing, -spacing])[: len(stroke)] / 2
    feet = np.stack([stroke, np.zeros_like(stroke)], axis=1)
    offset = feet - chain.hip + np.stack([hips, np.zeros_like(hips)], axis=1)
    theta = chain.leg.inverse(feet)
    n = len(stroke)
    return Stance(
        offset,
        chain.leg.jacobian(theta),
        np.full(n, FRICTION),
        np.full(n, ADHESION),
        np.tile(chain.torque_limits, (n, 1)),
        np.tile(WEIGHTS, (n, 1)),
        np.full(n, PULL_OFF),
    )


def static_wrench() -> np.ndarray:
    """Hanging still: the feet carry the weight along +x, no normal force, no moment."""
    return np.array([MASS * GRAVITY, 0.0, 0.0])
