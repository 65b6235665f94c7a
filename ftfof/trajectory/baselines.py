"""Trajectories legged robots commonly use, from P0 to P15 in the same total time (FTFOF §VI.D).

- polynomial: quintic (minimum-jerk) progress along x, a sextic bump 64 tau^3 (1 - tau)^3 in z;
  zero velocity and acceleration at both ends;
- cycloidal: the classic swing cycloid x = S (tau - sin(2 pi tau) / 2 pi),
  z = H (1 - cos(2 pi tau)) / 2 (zero end velocity, non-zero end vertical acceleration);
- ε-Bezier (ε-Bezier paper §III): a 3rd-order Bezier (eq. 7) whose control points clear an
  obstacle box (eq. 8-10), run through the truncated-sigmoid time warp of eq. 11;
- random Bezier: one feasible three-segment quintic drawn by the sampler (seeded).

Each is an analytic curve with exact velocity and acceleration, evaluated at arbitrary times.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import get_args

import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.trajectory.bezier import Samples
from ftfof.trajectory.piecewise import Sampled
from ftfof.trajectory.policy import ConstraintPolicy
from ftfof.trajectory.sampling import sample_feasible

Array = NDArray[np.float64]
BASELINE_NAMES: tuple[str, ...] = get_args(config.Baseline)


def _stack(x: Array, z: Array) -> Array:
    return np.stack([x, z], axis=-1)[None]


@dataclass(frozen=True)
class Polynomial:
    """Minimum-jerk x, sextic-bump z."""

    step: Array  # P15 - P0
    lift: float
    duration: float

    def sample(self, t: Array) -> Samples:
        T = self.duration
        u = np.clip(np.asarray(t, dtype=float) / T, 0.0, 1.0)
        q = (10 * u**3 - 15 * u**4 + 6 * u**5, (30 * u**2 - 60 * u**3 + 30 * u**4) / T)
        qa = (60 * u - 180 * u**2 + 120 * u**3) / T**2
        # b(u) = 64 u^3 (1-u)^3, peak 1 at u = 1/2
        b = 64 * u**3 * (1 - u) ** 3
        db = 64 * (3 * u**2 * (1 - u) ** 3 - 3 * u**3 * (1 - u) ** 2) / T
        ddb = 64 * (6 * u * (1 - u) ** 3 - 18 * u**2 * (1 - u) ** 2 + 6 * u**3 * (1 - u)) / T**2
        sx, sz = self.step
        return Samples(
            np.asarray(t, dtype=float),
            _stack(sx * q[0], sz * q[0] + self.lift * b),
            _stack(sx * q[1], sz * q[1] + self.lift * db),
            _stack(sx * qa, sz * qa + self.lift * ddb),
        )


@dataclass(frozen=True)
class Cycloidal:
    """Swing cycloid."""

    step: Array
    lift: float
    duration: float

    def sample(self, t: Array) -> Samples:
        T = self.duration
        u = np.clip(np.asarray(t, dtype=float) / T, 0.0, 1.0)
        w = 2 * np.pi
        q, dq, ddq = u - np.sin(w * u) / w, (1 - np.cos(w * u)) / T, w * np.sin(w * u) / T**2
        b, db, ddb = (
            (1 - np.cos(w * u)) / 2,
            w * np.sin(w * u) / (2 * T),
            w**2 * np.cos(w * u) / (2 * T**2),
        )
        sx, sz = self.step
        return Samples(
            np.asarray(t, dtype=float),
            _stack(sx * q, sz * q + self.lift * b),
            _stack(sx * dq, sz * dq + self.lift * db),
            _stack(sx * ddq, sz * ddq + self.lift * ddb),
        )


def eps_warp(u: Array, eps: float) -> tuple[Array, Array, Array]:
    """Truncated sigmoid time warp m(u) (ε-Bezier paper, eq. 11) and its first two derivatives.

    m(0) = 0, m(1) = 1, point-symmetric about (1/2, 1/2); tends to the identity as eps -> 0.
    """
    u = np.asarray(u, dtype=float)
    if eps < 1e-6:  # the series limit: m = u
        return u, np.ones_like(u), np.zeros_like(u)
    e = np.exp(eps)
    scale = (e + 1) / (e - 1)
    s = 1.0 / (np.exp(-2 * eps * (u - 0.5)) + 1.0)
    ds = 2 * eps * s * (1 - s)
    dds = 2 * eps * ds * (1 - 2 * s)
    return scale * (s - 1 / (e + 1)), scale * ds, scale * dds


def obstacle_apex(p0: Array, p3: Array, o1: Array, o2: Array) -> Array:
    """The point O_p the curve's apex must pass above (eq. 9-10).

    The lines from P0 through O1 and from P3 through O2 meet at O_p; a convex curve whose apex lies
    above O_p clears the obstacle box with top corners O1, O2.
    """
    # p0 + a (o1 - p0) = p3 + b (o2 - p3): eq. 9 written as a 2x2 linear system.
    A = np.column_stack([o1 - p0, p3 - o2])
    a, _ = np.linalg.solve(A, p3 - p0)
    return p0 + a * (o1 - p0)


@dataclass(frozen=True)
class EpsBezier:
    """Cubic Bezier P0, P1, P2, P3 (eq. 7) timed by the ε warp (eq. 11)."""

    points: Array  # (4, 2)
    eps: float
    duration: float

    @classmethod
    def clearing(
        cls, p0: Array, p3: Array, settings: config.EpsBezier, duration: float
    ) -> EpsBezier:
        """Control points whose apex sits above O_p with the requested clearance (eq. 8-10).

        P1 and P2 share the height H; the apex of a cubic with equal-height inner points is at
        m = 1/2 with height (P0z + P3z)/8 + 3H/4 and x = (P0x + 3 P1x + 3 P2x + P3x)/8 (eq. 8 for
        P0, P3 on the baseline). P1 is placed above O_p and P2 chosen so the apex is over O_p.
        """
        o1 = np.array([settings.obstacle_x[0], settings.obstacle_height])
        o2 = np.array([settings.obstacle_x[1], settings.obstacle_height])
        op = obstacle_apex(p0, p3, o1, o2)
        apex_z = op[1] * (1 + settings.clearance)
        H = (apex_z - (p0[1] + p3[1]) / 8) * 4 / 3
        x1 = op[0]
        x2 = (8 * op[0] - p0[0] - p3[0] - 3 * x1) / 3
        pts = np.array([p0, [x1, H], [x2, H], p3], dtype=float)
        return cls(pts, settings.epsilon, duration)

    def sample(self, t: Array) -> Samples:
        u = np.clip(np.asarray(t, dtype=float) / self.duration, 0.0, 1.0)
        m, dm, ddm = eps_warp(u, self.eps)
        P = self.points
        c = np.array([[1, 0, 0, 0], [-3, 3, 0, 0], [3, -6, 3, 0], [-1, 3, -3, 1]], dtype=float) @ P
        mm = m[:, None]
        pos = c[0] + c[1] * mm + c[2] * mm**2 + c[3] * mm**3
        d1 = c[1] + 2 * c[2] * mm + 3 * c[3] * mm**2
        d2 = 2 * c[2] + 6 * c[3] * mm
        T = self.duration
        vel = d1 * dm[:, None] / T
        acc = (d2 * dm[:, None] ** 2 + d1 * ddm[:, None]) / T**2
        return Samples(np.asarray(t, dtype=float), pos[None], vel[None], acc[None])


def common_trajectories(
    policy: ConstraintPolicy, settings: config.Baselines, seed: int
) -> dict[str, Sampled]:
    """The four common trajectories (FTFOF §VI.D) for a robot, from P0 to P15 in its time T3.

    The random Bezier is the first feasible draw of the robot's own sampler with ``seed``: the
    pipeline passes its own "baselines" stream (``ftfof.seeds``), independent of the training
    samples' draws.
    """
    T = policy.timing.T3
    step = policy.p15 - policy.p0
    X = sample_feasible(policy, 1, seed).X[0]
    return {
        "polynomial": Polynomial(step, settings.lift_height, T),
        "cycloidal": Cycloidal(step, settings.lift_height, T),
        "random_bezier": BezierTrajectory(policy, X),
        "eps_bezier": EpsBezier.clearing(policy.p0, policy.p15, settings.eps_bezier, T),
    }


@dataclass(frozen=True)
class BezierTrajectory:
    """A three-segment quintic Bezier of a robot, with the same interface as the baselines."""

    policy: ConstraintPolicy
    X: Array  # (12,)

    def sample(self, t: Array) -> Samples:
        return self.policy.sample(self.X[None], np.asarray(t, dtype=float))
