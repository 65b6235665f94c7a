"""The optimum as a controller reads it: time-sampled foot position, velocity and joint angles."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.kinematics.legs import Leg, within_limits
from ftfof.trajectory.policy import ConstraintPolicy

Array = NDArray[np.float64]

COLUMNS = (
    "t [s]",
    "x [m]",
    "z [m]",
    "vx [m/s]",
    "vz [m/s]",
    "q1 [rad]",
    "q2 [rad]",
    "q3 [rad]",
    "dq1 [rad/s]",
    "dq2 [rad/s]",
    "dq3 [rad/s]",
)


class ExportRateError(ValueError):
    """The export rate is too low to sample the trajectory (the rate's fault, not the leg's)."""


@dataclass(frozen=True)
class ControllerTrajectory:
    table: Array  # (n, len(COLUMNS))
    within_joint_limits: bool
    peak_joint_speed: Array  # (3,) rad/s

    @property
    def columns(self) -> tuple[str, ...]:
        return COLUMNS


def controller_trajectory(
    policy: ConstraintPolicy, leg: Leg, X: Array, rate_hz: float
) -> ControllerTrajectory:
    """Sample the Bezier ``X`` (12,) over [0, T3] at ``rate_hz`` and solve the leg's IK.

    Joint rates solve J(q) dq = v exactly through the leg's sagittal parameterisation (two free
    joints, the third following from them). Raises ExportRateError for a rate giving fewer than 3
    samples, ValueError at the first instant the leg cannot reach.
    """
    T3 = policy.timing.T3
    t = np.linspace(0.0, T3, int(np.floor(T3 * rate_hz + 1e-9)) + 1)
    if t.size < 3:
        raise ExportRateError(
            f"export rate {rate_hz} Hz gives fewer than 3 samples over T3 = {T3} s"
        )
    s = policy.sample(np.asarray(X, dtype=float)[None], t)
    position, velocity = s.position[0], s.velocity[0]
    theta = leg.inverse(position)
    bad = np.flatnonzero(~np.all(np.isfinite(theta), axis=1))
    if bad.size:
        i = int(bad[0])
        x, z = 1e3 * position[i]
        raise ValueError(
            f"the leg cannot reach the foot point ({x:.2f}, {z:.2f}) mm at t = {t[i]:.4f} s"
        )
    rates = _joint_rates(leg, theta, velocity)
    table = np.column_stack([t, position, velocity, theta, rates])
    inside = bool(np.all(within_limits(theta, leg.joint_limits)))
    return ControllerTrajectory(table, inside, np.abs(rates).max(axis=0))


def _joint_rates(leg: Leg, theta: Array, velocity: Array) -> Array:
    """dq (n, 3) from the foot velocity: dq = S r with S the sagittal completion, (J S) r = v."""
    n = theta.shape[0]
    S = np.stack(
        [leg.sagittal_rates(theta, np.broadcast_to(e, (n, 2))) for e in np.eye(2)], axis=-1
    )
    A = np.einsum("nij,njk->nik", leg.jacobian(theta), S)
    free = np.linalg.solve(A, velocity[..., None])[..., 0]
    return np.einsum("nij,nj->ni", S, free)
