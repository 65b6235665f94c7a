"""Leg kinematics in the trajectory frame (x along the wall, z away from it, origin P0).

Two leg types, both vectorised over leading axes of their inputs:

- :class:`PlanarLeg` — hip, knee and ankle in the x-z plane; the ankle keeps the foot plate
  parallel to the wall (docs/simulator.md, Legs).
- :class:`SpatialLeg` — the 3-DOF leg of the ε-Bezier paper (D-H table I, forward eq. 5, analytic
  inverse eq. 6); the foot trajectory lies in the leg's plane y = 0.

Each leg has three joints but only two degrees of freedom in the sagittal plane: the third
("dependent") joint is fixed by the plane condition. ``sagittal_angles`` / ``sagittal_rates``
complete a pair of free joints with that dependent joint; the reach searches of
:mod:`ftfof.kinematics.limits` work through them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

import ftfof.config as config

Array = NDArray[np.float64]


class Leg(Protocol):
    """What the constraint policy, the controller export and the joint-level simulator need."""

    joint_limits: Array  # (3, 2) rad
    speed_limits: Array  # (3,) rad/s
    free_joints: tuple[int, int]  # the two joints searched; the third is dependent

    def forward(self, theta: Array) -> Array: ...  # (..., 3) -> (..., 2) foot x, z

    def inverse(self, p: Array) -> Array: ...  # (..., 2) -> (..., 3); NaN where unreachable

    def jacobian(self, theta: Array) -> Array: ...  # (..., 3) -> (..., 2, 3) d(x, z)/d(theta)

    def sagittal_angles(self, free: Array) -> Array: ...  # (..., 2) -> (..., 3)

    def sagittal_rates(self, theta: Array, free_rates: Array) -> Array: ...  # -> (..., 3)


def _two_link(a: Array, b: Array, l1: float, l2: float, sign: float) -> tuple[Array, Array]:
    """Angles of a two-link chain reaching (a, b): first from the a-axis, second relative."""
    c2 = (a**2 + b**2 - l1**2 - l2**2) / (2 * l1 * l2)
    with np.errstate(invalid="ignore"):
        q2 = sign * np.arccos(np.where(np.abs(c2) <= 1 + 1e-12, np.clip(c2, -1, 1), np.nan))
    q1 = np.arctan2(b, a) - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
    return q1, q2


def _wrap(angle: Array) -> Array:
    return (angle + np.pi) % (2 * np.pi) - np.pi


@dataclass(frozen=True)
class PlanarLeg:
    """Planar three-joint leg; angles from +x towards +z, knee and ankle relative."""

    hip: Array  # (2,)
    l1: float
    l2: float
    foot_offset: Array  # contact point relative to the ankle, plate parallel to the wall
    joint_limits: Array
    speed_limits: Array
    free_joints: tuple[int, int] = (0, 1)

    @property
    def knee_sign(self) -> float:
        """IK branch: the knee bends to the side its joint range lies on."""
        return 1.0 if self.joint_limits[1].mean() >= 0 else -1.0

    def forward(self, theta: Array) -> Array:
        theta = np.asarray(theta, dtype=float)
        q1, q12 = theta[..., 0], theta[..., 0] + theta[..., 1]
        plate = q12 + theta[..., 2]
        ox, oz = self.foot_offset
        x = self.hip[0] + self.l1 * np.cos(q1) + self.l2 * np.cos(q12)
        z = self.hip[1] + self.l1 * np.sin(q1) + self.l2 * np.sin(q12)
        x = x + ox * np.cos(plate) - oz * np.sin(plate)
        z = z + ox * np.sin(plate) + oz * np.cos(plate)
        return np.stack([x, z], axis=-1)

    def inverse(self, p: Array) -> Array:
        p = np.asarray(p, dtype=float)
        ankle = p - self.foot_offset - self.hip
        q1, q2 = _two_link(ankle[..., 0], ankle[..., 1], self.l1, self.l2, self.knee_sign)
        q1 = _wrap(q1)
        return np.stack([q1, q2, -q1 - q2], axis=-1)

    def jacobian(self, theta: Array) -> Array:
        theta = np.asarray(theta, dtype=float)
        q1, q12 = theta[..., 0], theta[..., 0] + theta[..., 1]
        plate = q12 + theta[..., 2]
        ox, oz = self.foot_offset
        # d(contact)/d(plate angle): the offset vector rotated by +90 degrees.
        dpx = -ox * np.sin(plate) - oz * np.cos(plate)
        dpz = ox * np.cos(plate) - oz * np.sin(plate)
        J = np.empty((*theta.shape[:-1], 2, 3))
        J[..., 0, 0] = -self.l1 * np.sin(q1) - self.l2 * np.sin(q12) + dpx
        J[..., 1, 0] = self.l1 * np.cos(q1) + self.l2 * np.cos(q12) + dpz
        J[..., 0, 1] = -self.l2 * np.sin(q12) + dpx
        J[..., 1, 1] = self.l2 * np.cos(q12) + dpz
        J[..., 0, 2] = dpx
        J[..., 1, 2] = dpz
        return J

    def sagittal_angles(self, free: Array) -> Array:
        free = np.asarray(free, dtype=float)
        return np.stack([free[..., 0], free[..., 1], -free[..., 0] - free[..., 1]], axis=-1)

    def sagittal_rates(self, theta: Array, free_rates: Array) -> Array:
        r = np.asarray(free_rates, dtype=float)
        return np.stack([r[..., 0], r[..., 1], -r[..., 0] - r[..., 1]], axis=-1)


@dataclass(frozen=True)
class SpatialLeg:
    """ε-Bezier paper leg: hip ab/adduction theta1, hip pitch theta2, knee theta3 (eq. 5-6)."""

    hip: Array  # origin of {O_1} in the trajectory frame (x, z)
    y0: float
    d1: float
    d2: float
    d3: float
    d4: float
    joint_limits: Array
    speed_limits: Array
    free_joints: tuple[int, int] = (1, 2)

    def _extension(self, theta: Array) -> tuple[Array, Array]:
        """Radial extension L and the forward reach px of the pitch chain (eq. 5)."""
        q2, q23 = theta[..., 1], theta[..., 1] + theta[..., 2]
        L = self.d1 + self.d4 + self.d3 * np.cos(q23) + self.d2 * np.cos(q2)
        px = self.d3 * np.sin(q23) + self.d2 * np.sin(q2)
        return L, px

    def forward3(self, theta: Array) -> Array:
        """(x, y, z) of the foot, eq. 5 with the chain origin placed at ``hip``."""
        theta = np.asarray(theta, dtype=float)
        L, px = self._extension(theta)
        x = self.hip[0] + px
        y = self.y0 + np.sin(theta[..., 0]) * L
        z = self.hip[1] - np.cos(theta[..., 0]) * L
        return np.stack([x, y, z], axis=-1)

    def forward(self, theta: Array) -> Array:
        return self.forward3(theta)[..., [0, 2]]

    def inverse3(self, p: Array) -> Array:
        """Analytic inverse (eq. 6) of (x, y, z); the knee branch theta3 >= 0 as in the paper."""
        p = np.asarray(p, dtype=float)
        dy, dz = p[..., 1] - self.y0, self.hip[1] - p[..., 2]
        q1 = np.arctan2(dy, dz)
        k = np.hypot(dy, dz) - self.d1 - self.d4
        q2, q3 = _two_link(k, p[..., 0] - self.hip[0], self.d2, self.d3, 1.0)
        theta = np.stack([q1, q2, q3], axis=-1)
        return np.where(np.isnan(q3)[..., None], np.nan, theta)

    def inverse(self, p: Array) -> Array:
        p = np.asarray(p, dtype=float)
        return self.inverse3(np.stack([p[..., 0], np.zeros_like(p[..., 0]), p[..., 1]], axis=-1))

    def jacobian3(self, theta: Array) -> Array:
        theta = np.asarray(theta, dtype=float)
        L, px = self._extension(theta)
        s1, c1 = np.sin(theta[..., 0]), np.cos(theta[..., 0])
        q23 = theta[..., 1] + theta[..., 2]
        dL = np.stack([np.zeros_like(L), -px, -self.d3 * np.sin(q23)], axis=-1)
        J = np.empty((*theta.shape[:-1], 3, 3))
        J[..., 0, 0] = 0.0
        J[..., 0, 1] = L - self.d1 - self.d4
        J[..., 0, 2] = self.d3 * np.cos(q23)
        J[..., 1, :] = s1[..., None] * dL
        J[..., 1, 0] = c1 * L
        J[..., 2, :] = -c1[..., None] * dL
        J[..., 2, 0] = s1 * L
        return J

    def jacobian(self, theta: Array) -> Array:
        return self.jacobian3(theta)[..., [0, 2], :]

    def sagittal_angles(self, free: Array) -> Array:
        """Completes (theta2, theta3) with the abduction theta1 that keeps the foot at y = 0."""
        free = np.asarray(free, dtype=float)
        probe = np.stack([np.zeros_like(free[..., 0]), free[..., 0], free[..., 1]], axis=-1)
        L, _ = self._extension(probe)
        with np.errstate(invalid="ignore", divide="ignore"):
            q1 = np.arcsin(np.where(np.abs(self.y0) <= np.abs(L), -self.y0 / L, np.nan))
        return np.stack([q1, free[..., 0], free[..., 1]], axis=-1)

    def sagittal_rates(self, theta: Array, free_rates: Array) -> Array:
        """Completes (dtheta2, dtheta3) with the dtheta1 that keeps dy/dt = 0."""
        r = np.asarray(free_rates, dtype=float)
        Jy = self.jacobian3(theta)[..., 1, :]
        with np.errstate(invalid="ignore", divide="ignore"):
            q1dot = -(Jy[..., 1] * r[..., 0] + Jy[..., 2] * r[..., 1]) / Jy[..., 0]
        return np.stack([q1dot, r[..., 0], r[..., 1]], axis=-1)


def build_leg(settings: config.PlanarLeg | config.SpatialLeg) -> PlanarLeg | SpatialLeg:
    """The leg model a preset describes."""
    limits = np.asarray(settings.joint_limits, dtype=float)
    speeds = np.asarray(settings.joint_speed_limits, dtype=float)
    hip = np.array([settings.hip.x, settings.hip.z])
    if isinstance(settings, config.PlanarLeg):
        offset = np.array([settings.foot_offset.x, settings.foot_offset.z])
        return PlanarLeg(hip, *settings.links, offset, limits, speeds)
    return SpatialLeg(hip, settings.lateral_offset, *settings.d, limits, speeds)


def within_limits(theta: Array, limits: Array, tol: float = 1e-9) -> NDArray[np.bool_]:
    """True where every joint of ``theta`` (..., 3) lies inside its range."""
    return np.all((theta >= limits[:, 0] - tol) & (theta <= limits[:, 1] + tol), axis=-1)


def joint_rates(leg: Leg, theta: Array, velocity: Array) -> Array:
    """dq (..., 3) of the foot's ``velocity`` (..., 2) at ``theta`` (..., 3): dq = S r with S
    the sagittal completion of the two free joints' rates r, and (J S) r = v exactly."""
    lead = theta.shape[:-1]
    S = np.stack(
        [leg.sagittal_rates(theta, np.broadcast_to(e, (*lead, 2))) for e in np.eye(2)], axis=-1
    )
    A = np.einsum("...ij,...jk->...ik", leg.jacobian(theta), S)
    det = A[..., 0, 0] * A[..., 1, 1] - A[..., 0, 1] * A[..., 1, 0]
    vx, vz = velocity[..., 0], velocity[..., 1]
    with np.errstate(invalid="ignore", divide="ignore"):  # a singular pose: inf, not an error
        free = np.stack(
            [
                (A[..., 1, 1] * vx - A[..., 0, 1] * vz) / det,
                (A[..., 0, 0] * vz - A[..., 1, 0] * vx) / det,
            ],
            axis=-1,
        )
    return np.einsum("...ij,...j->...i", S, free)


def joint_excess(leg: Leg, position: Array, velocity: Array) -> Array:
    """How far a foot path (..., n_t, 2) and its velocity take the leg past its joints, per
    path (...): the largest of each joint's excess over its range (rad) and its rate's excess
    over its speed limit as a fraction of that limit; > 0 where the leg cannot run the path, 1
    where it cannot reach a point at all. The paper's Ppl and Vpl bound the foot's box and
    speed; this is the leg itself, which a controller export checks point by point."""
    theta = leg.inverse(position)
    lo, hi = leg.joint_limits[:, 0], leg.joint_limits[:, 1]
    rates = joint_rates(leg, np.where(np.isfinite(theta), theta, 0.0), velocity)
    outside = np.maximum(lo - theta, theta - hi)
    fast = np.abs(rates) / leg.speed_limits - 1.0
    worst = np.maximum(outside, fast).max(axis=-1)  # NaN off the reach, inf at a singular pose
    return np.where(np.isfinite(worst), worst, 1.0).max(axis=-1)
