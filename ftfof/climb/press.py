"""The landed foot's landing press: the platform's integral loop, run on the robot's wall patches.

The robot starts with every pad bonded at the pre-pressure; on a vertical wall no normal force
but the feet's own acts, so a foot presses only against the others' pull: one at a time, on
landing. Through its landing hold, a loop on the landed leg's wall patch
(:func:`ftfof.sim.prestep.press_integral`) deepens its press until the patch's sensor reads a;
the press is released over the body's advance that follows (a press held through the stance would
make the stance feet push against each other: on a wall nothing else takes it).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.gait import LEGS, Gait
from ftfof.climb.model import Climber
from ftfof.config import Sensor
from ftfof.sim.model import in_series, pad_stiffnesses
from ftfof.sim.press import press_integral
from ftfof.trajectory.blend import min_jerk

Array = NDArray[np.float64]


class LandingPress:
    """Each leg's press depth into the wall (m), found afresh at each landing."""

    def __init__(
        self, gait: Gait, sensor: Sensor, patches: Array, pre_pressure: float, stiffness: float
    ):
        self.gait, self.sensor, self.patches = gait, sensor, patches
        self.pre_pressure, self.stiffness = pre_pressure, stiffness
        self.depth = np.zeros(LEGS)

    def step(self, leg: int, tau: float, q: Array, qd: Array, h: float) -> None:
        """One solver step of ``h`` for the leg in its step, ``tau`` after its lift-off: zero
        through its swing (a depth kept from the last landing would jump the foot into the wall
        at the next lift-off), the loop through its landing hold, held after."""
        gait = self.gait
        if tau < gait.swing:
            self.depth[leg] = 0.0
            return
        if tau >= gait.swing + gait.hold:
            return
        plate, target = self.patches[leg], self.pre_pressure
        self.depth[leg] = press_integral(
            self.sensor, plate, q, qd, h, target, self.depth[leg], self.stiffness
        )

    def applied(self, tau: float, leg: int) -> Array:
        """Each leg's press into the wall now: the landing leg's loop depth through its swing
        and hold, released over the advance that follows (minimum jerk)."""
        gait = self.gait
        out = np.zeros(LEGS)
        if leg < 0:
            return out
        release = (tau - gait.swing - gait.hold) / gait.shift
        out[leg] = self.depth[leg] * (1.0 - float(min_jerk(np.array(release))[0]))
        return out


def press_stiffness(robot: Climber) -> float:
    """Estimate of a leg's press path stiffness: joints at the foot, sensor, contact, backing,
    and the foot mount where the robot has one."""
    spec = robot.spec
    mech = spec.robot.platform
    l1, l2 = robot.chain.links
    pad = spec.robot.foot.pad_length
    parts = [
        mech.joint_gains[0] / max(l1, l2) ** 2,
        spec.platform.sensor.stiffness,
        *pad_stiffnesses(robot.law, mech.foot, mech.film, pad),
    ]
    mount = spec.robot.climber.foot_mount_stiffness if spec.robot.climber else None
    if mount is not None:
        parts.append(mount.z)
    return in_series(parts)
