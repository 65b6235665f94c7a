"""The CoM planner's cubic Hermite pieces (climbing_slip §3): a piece's s, s' and s'' from its
data (s0, v0, s1, v1), and the checks on it where its time functions peak (Proposition 1).

A piece with one time function, s = x f(t) at a constant s'', is checked exactly at f's
extremes (:func:`points`); one with two on the Bezier control points of (s(t), s''(t)) on
``ARCS`` sub-arcs (:func:`hull`), whose convex hull holds the curve: sufficient, a little
conservative.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]
ARCS = 4  # sub-arcs of a cubic piece's Bezier check (the hull's excess falls as 1 / ARCS^2)


def hermite_rows(tau: Array, T: float) -> tuple[Array, Array, Array]:
    """Rows giving s, s' and s'' at local times ``tau`` of a cubic Hermite piece of duration
    T from its data (s0, v0, s1, v1), each (N, 4)."""
    u = np.asarray(tau, float) / T
    u2, u3 = u * u, u * u * u
    value = np.stack([1 - 3 * u2 + 2 * u3, T * (u - 2 * u2 + u3), 3 * u2 - 2 * u3, T * (u3 - u2)])
    rate = np.stack([6 * (u2 - u) / T, 1 - 4 * u + 3 * u2, 6 * (u - u2) / T, 3 * u2 - 2 * u])
    acc = np.stack([(12 * u - 6) / T**2, (6 * u - 4) / T, (6 - 12 * u) / T**2, (6 * u - 2) / T])
    return value.T, rate.T, acc.T


def points(tau: Array, T: float) -> tuple[Array, Array]:
    """Checks on the curve itself at ``tau``: exact where one time function peaks there."""
    value, _, acc = hermite_rows(tau, T)
    return value, acc


def hull(T: float, arcs: int = ARCS) -> tuple[Array, Array]:
    """Checks at the Bezier control points of (s, s'') on ``arcs`` equal sub-arcs: s cubic,
    s'' linear raised to degree 3, so the curve lies in their convex hull."""
    knots = np.linspace(0.0, T, arcs + 1)
    value, rate, acc = hermite_rows(knots, T)
    h = (T / arcs) / 3
    a0, a1 = acc[:-1], acc[1:]
    s_rows = np.stack([value[:-1], value[:-1] + h * rate[:-1], value[1:] - h * rate[1:]], 1)
    a_rows = np.stack([a0, (2 * a0 + a1) / 3, (a0 + 2 * a1) / 3], 1)
    s_rows = np.concatenate([s_rows.reshape(-1, 4), value[-1:]])
    return s_rows, np.concatenate([a_rows.reshape(-1, 4), acc[-1:]])


def power(T: float) -> Array:
    """(4, 4): Hermite data (s0, v0, s1, v1) to power coefficients of s(tau) on [0, T]."""
    return np.array(
        [
            [1, 0, 0, 0],
            [0, 1, 0, 0],
            [-3 / T**2, -2 / T, 3 / T**2, -1 / T],
            [2 / T**3, 1 / T**2, -2 / T**3, 1 / T**2],
        ]
    )
