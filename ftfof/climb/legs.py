"""Each leg as the planar hip-knee-ankle chain the climbing robot is built from.

The climbing model is sagittal (x up the wall, z out of it): every leg is a chain of three
revolute joints in that plane, the third keeping the foot's sole parallel to the wall, with the
foot's ankle at the chain's end. A ``planar3`` leg is that chain already. A ``spatial3`` leg (the
ε-Bezier paper's) works in the plane through its hip pitch and knee; its abduction joint is held
at zero on the wall (the foot path lies in y = 0), its radial offsets d1 and d4 shift the hip,
and the foot's own ankle height replaces d4 at the chain's end. Its third sagittal joint is a
virtual one without a servo limit: MST-Q's foot has no ankle joint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.kinematics.legs import PlanarLeg

Array = NDArray[np.float64]
UNLIMITED = (-math.pi, math.pi)


@dataclass(frozen=True)
class SagittalChain:
    """A leg as the climbing robot's planar chain, with the limits in the chain's angles."""

    leg: PlanarLeg  # in the leg's trajectory frame (origin P0, the foot's start on the wall)
    torque_limits: Array  # (3,) N m; inf for a virtual joint
    offset: Array  # (3,) chain angle = preset angle + offset, for the joints the preset has
    preset_joints: tuple[int, int, int]  # the preset's joint behind each chain joint (-1: none)

    @property
    def hip(self) -> Array:
        return self.leg.hip

    @property
    def links(self) -> tuple[float, float]:
        return self.leg.l1, self.leg.l2


def sagittal_chain(
    settings: config.PlanarLeg | config.SpatialLeg,
    torque_limits: tuple[float, float, float],
    ankle_height: float,
) -> SagittalChain:
    """The chain of a preset's leg; the foot's ankle sits ``ankle_height`` above its pad."""
    foot = np.array([0.0, -ankle_height])
    if isinstance(settings, config.PlanarLeg):
        leg = PlanarLeg(
            np.array([settings.hip.x, settings.hip.z]),
            *settings.links,
            foot,
            np.asarray(settings.joint_limits, dtype=float),
            np.asarray(settings.joint_speed_limits, dtype=float),
        )
        return SagittalChain(leg, np.asarray(torque_limits, float), np.zeros(3), (0, 1, 2))
    d1, d2, d3, d4 = settings.d
    limits = np.asarray(settings.joint_limits, dtype=float)
    speeds = np.asarray(settings.joint_speed_limits, dtype=float)
    # pitch theta2 turns the thigh from the downward radial axis toward +x: chain angle - pi / 2
    offset = np.array([-math.pi / 2, 0.0, 0.0])
    leg = PlanarLeg(
        np.array([settings.hip.x, settings.hip.z - d1 - d4 + ankle_height]),
        d2,
        d3,
        foot,
        np.array([limits[1] + offset[0], limits[2], UNLIMITED]),
        np.array([speeds[1], speeds[2], np.inf]),
    )
    torques = np.array([torque_limits[1], torque_limits[2], np.inf])
    return SagittalChain(leg, torques, offset, (1, 2, -1))


def stroke_breach(chain: SagittalChain, stride: float, samples: int = 50) -> str:
    """ "" when every leg reaches its stance stroke, P0 to P15 along the wall (``stride`` long),
    within its joint ranges; else where it leaves them (for a message)."""
    x = np.linspace(0.0, stride, samples)
    theta = chain.leg.inverse(np.stack([x, np.zeros_like(x)], axis=1))
    limits = chain.leg.joint_limits
    inside = np.isfinite(theta).all(axis=1) & np.all(
        (theta >= limits[:, 0]) & (theta <= limits[:, 1]), axis=1
    )
    if inside.all():
        return ""
    at = 1e3 * x[np.argmin(inside)]
    return f"every leg's stance stroke leaves its joint range {at:.0f} mm along the wall"
