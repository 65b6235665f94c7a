"""Three-segment quintic Bezier foot trajectory (FTFOF §III.A).

Sixteen control points P0..P15; segments P0-P5 on [0, T1], P5-P10 on [T1, T2], P10-P15 on
[T2, T3]. The 12 decision values fix P3, P4, P5, P10, P11, P12; P0 and P15 come from the robot,
P1 = P2 = P0 and P13 = P14 = P15 give zero end velocity and acceleration (eq. 6), and P6..P9
follow from duration-aware C2 joins, so the *physical* velocity and acceleration are continuous
even when the segments last different times (eq. 5 is the equal-duration special case).

Every control point is a linear function of the decision vector, so a trajectory sampled at fixed
times is ``weights @ control_points``: one einsum evaluates a whole population.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from math import comb

import numpy as np
from numpy.typing import NDArray

from ftfof.config import Timing

DECISION_NAMES: tuple[str, ...] = (
    "P3x",
    "P4x",
    "P5x",
    "P10x",
    "P11x",
    "P12x",
    "P3z",
    "P4z",
    "P5z",
    "P10z",
    "P11z",
    "P12z",
)
FREE_POINTS = (3, 4, 5, 10, 11, 12)
N_POINTS = 16
DEGREE = 5

Array = NDArray[np.float64]


def same_trajectory(X: Array, rows: Array | None) -> NDArray[np.bool_]:
    """Per row of ``X``, whether it is one of ``rows`` (decision rows, to a nanometre: decision
    values pass through a policy's free variables and back, and through Parquet)."""
    if rows is None or len(rows) == 0 or len(X) == 0:
        return np.zeros(len(X), dtype=bool)
    return (np.abs(X[:, None, :] - rows[None, :, :]).max(axis=-1) <= 1e-9).any(axis=1)


def decision_to_points(X: Array) -> Array:
    """(pop, 12) decision vectors in the paper's order -> (pop, 6, 2): P3 P4 P5 P10 P11 P12."""
    X = np.asarray(X, dtype=float)
    return np.stack([X[..., :6], X[..., 6:]], axis=-1)


def points_to_decision(points: Array) -> Array:
    """Inverse of :func:`decision_to_points`."""
    return np.concatenate([points[..., 0], points[..., 1]], axis=-1)


def control_points(X: Array, p0: Array, p15: Array, timing: Timing) -> Array:
    """All 16 control points of (pop, 12) decision vectors: (pop, 16, 2)."""
    return control_points_from_free(decision_to_points(X), p0, p15, timing)


def control_points_from_free(free: Array, p0: Array, p15: Array, timing: Timing) -> Array:
    """All 16 control points from P3 P4 P5 P10 P11 P12 given as (pop, 6, d), any dimension d.

    Applies the smooth-end conditions (eq. 6) and C2 joins that account for the segments' durations.
    """
    free = np.asarray(free, dtype=float)
    pop, d = free.shape[:-2], free.shape[-1]
    P = np.empty((*pop, N_POINTS, d))
    P[..., 0:3, :] = np.broadcast_to(np.asarray(p0, dtype=float), (*pop, 1, d))
    P[..., 13:16, :] = np.broadcast_to(np.asarray(p15, dtype=float), (*pop, 1, d))
    P[..., FREE_POINTS, :] = free
    d1, d2, d3 = timing.durations
    r, rp = d2 / d1, d2 / d3
    P3, P4, P5 = P[..., 3, :], P[..., 4, :], P[..., 5, :]
    P10, P11, P12 = P[..., 10, :], P[..., 11, :], P[..., 12, :]
    P[..., 6, :] = P5 + r * (P5 - P4)
    P[..., 7, :] = 2 * P[..., 6, :] - P5 + r**2 * (P5 - 2 * P4 + P3)
    P[..., 9, :] = P10 + rp * (P10 - P11)
    P[..., 8, :] = 2 * P[..., 9, :] - P10 + rp**2 * (P10 - 2 * P11 + P12)
    return P


def bernstein(n: int, s: Array) -> Array:
    """Bernstein basis of degree ``n`` at parameters ``s``: (len(s), n + 1)."""
    s = np.asarray(s, dtype=float)[:, None]
    i = np.arange(n + 1)
    coeff = np.array([comb(n, k) for k in range(n + 1)], dtype=float)
    return coeff * s**i * (1.0 - s) ** (n - i)


def _derivative_weights(order: int) -> Array:
    """Maps the 6 control points of a quintic to the (5 - order + 1) points of its derivative.

    d/ds of a degree-n curve has control points n(P_{i+1} - P_i) (eq. 3-4).
    """
    W = np.eye(DEGREE + 1)
    for k in range(order):
        n = DEGREE - k
        D = np.zeros((n, n + 1))
        D[np.arange(n), np.arange(n)] = -n
        D[np.arange(n), np.arange(n) + 1] = n
        W = D @ W
    return W


@dataclass(frozen=True)
class Basis:
    """Weights that turn the 16 control points into samples at fixed times."""

    t: Array  # (n_t,)
    position: Array  # (n_t, 16)
    velocity: Array  # (n_t, 16), per second
    acceleration: Array  # (n_t, 16), per second squared


def basis(timing: Timing, t: Array) -> Basis:
    """Position/velocity/acceleration weights at times ``t`` (each time in exactly one segment)."""
    t = np.asarray(t, dtype=float)
    return _basis_cached(timing, tuple(t.tolist()))


@lru_cache(maxsize=32)
def _basis_cached(timing: Timing, t_key: tuple[float, ...]) -> Basis:
    t = np.asarray(t_key)
    b = timing.bounds
    seg = np.clip(np.searchsorted(b, t, side="left") - 1, 0, 2)
    weights = [np.zeros((t.size, N_POINTS)) for _ in range(3)]
    for k in range(3):
        sel = seg == k
        if not sel.any():
            continue
        dur = b[k + 1] - b[k]
        s = np.clip((t[sel] - b[k]) / dur, 0.0, 1.0)
        cols = slice(5 * k, 5 * k + 6)
        for order, W in enumerate(weights):
            local = bernstein(DEGREE - order, s) @ _derivative_weights(order)
            W[np.ix_(sel, np.arange(N_POINTS)[cols])] = local / dur**order
    for W in weights:
        W.setflags(write=False)
    return Basis(t, *weights)


class Samples:
    """A population's trajectories sampled in time: each array (pop, n_t, d), computed on first
    use (one GEMM each on component-major points), so callers pay only for what they read."""

    def __init__(
        self,
        t: Array,
        position: Array | None = None,
        velocity: Array | None = None,
        acceleration: Array | None = None,
        *,
        points: Array | None = None,
        basis: Basis | None = None,
    ):
        self.t = t
        self._given = {"position": position, "velocity": velocity, "acceleration": acceleration}
        self._points, self._basis = points, basis

    def _sampled(self, name: str) -> Array:
        value = self._given[name]
        if value is None:
            P, B = self._points, self._basis
            assert P is not None and B is not None, f"{name} was neither given nor derivable"
            lead, d = P.shape[:-2], P.shape[-1]
            comp = np.ascontiguousarray(np.moveaxis(P, -1, 0)).reshape(-1, N_POINTS)
            W = getattr(B, name)
            value = np.moveaxis((comp @ W.T).reshape(d, *lead, len(B.t)), 0, -1)
            self._given[name] = value
        return value

    @property
    def position(self) -> Array:
        return self._sampled("position")

    @property
    def velocity(self) -> Array:
        return self._sampled("velocity")

    @property
    def acceleration(self) -> Array:
        return self._sampled("acceleration")


def evaluate(X: Array, p0: Array, p15: Array, timing: Timing, t: Array) -> Samples:
    """Position, velocity and acceleration of every trajectory in ``X`` at times ``t``."""
    return evaluate_points(control_points(np.atleast_2d(X), p0, p15, timing), timing, t)


def evaluate_points(P: Array, timing: Timing, t: Array) -> Samples:
    """Samples of trajectories given by their 16 control points (pop, 16, d)."""
    B = basis(timing, t)
    return Samples(B.t, points=np.asarray(P, dtype=float), basis=B)
