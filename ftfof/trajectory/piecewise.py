"""Piecewise quintic trajectories: one representation for every foot trajectory the simulator runs.

A quintic is fixed by position, velocity and acceleration at both ends of its interval, so
quintic Hermite interpolation of (p, v, a) at knots is exact for the three-segment Bezier (knots
0, T1, T2, T3) and for any quintic, and converges like h^6 for the cycloid and the ε-Bezier.
The same coefficients evaluate with numpy or compile to an ``exudyn.symbolic`` expression (the
simulator's trajectory user functions run in C++ with exact derivatives).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from ftfof.trajectory.bezier import Samples

Array = NDArray[np.float64]


class Sampled(Protocol):
    """Anything with exact position/velocity/acceleration at given times (single trajectory)."""

    def sample(self, t: Array) -> Samples: ...


@dataclass(frozen=True)
class PiecewiseQuintic:
    """x_d(t) = sum_k c[seg, d, k] (t - knots[seg])^k on each [knots[seg], knots[seg+1]].

    Before the first knot the start point is held, after the last the end point (zero velocity).
    """

    knots: Array  # (m + 1,)
    coeffs: Array  # (m, d, 6)

    @classmethod
    def from_samples(cls, samples: Samples) -> PiecewiseQuintic:
        """Quintic Hermite interpolation of one trajectory's samples (their times are the knots)."""
        t = np.asarray(samples.t, dtype=float)
        p, v, a = samples.position[0], samples.velocity[0], samples.acceleration[0]
        h = np.diff(t)[:, None]
        p0, p1, v0, v1, a0, a1 = p[:-1], p[1:], v[:-1], v[1:], a[:-1], a[1:]
        # Standard quintic Hermite coefficients in the local variable s = t - t0.
        c0, c1, c2 = p0, v0, a0 / 2
        c3 = (20 * (p1 - p0) - (8 * v1 + 12 * v0) * h - (3 * a0 - a1) * h**2) / (2 * h**3)
        c4 = (30 * (p0 - p1) + (14 * v1 + 16 * v0) * h + (3 * a0 - 2 * a1) * h**2) / (2 * h**4)
        c5 = (12 * (p1 - p0) - 6 * (v1 + v0) * h - (a0 - a1) * h**2) / (2 * h**5)
        return cls(t, np.stack([c0, c1, c2, c3, c4, c5], axis=-1))

    @classmethod
    def fit(cls, trajectory: Sampled, duration: float, segments: int) -> PiecewiseQuintic:
        """Hermite fit of any analytic trajectory on ``segments`` equal pieces of [0, duration]."""
        return cls.from_samples(trajectory.sample(np.linspace(0.0, duration, segments + 1)))

    @property
    def duration(self) -> float:
        return float(self.knots[-1] - self.knots[0])

    def sample(self, t: Array) -> Samples:
        """Position, velocity and acceleration at ``t`` (held constant outside the knots)."""
        t = np.asarray(t, dtype=float)
        seg = np.clip(np.searchsorted(self.knots, t, side="right") - 1, 0, len(self.coeffs) - 1)
        s = np.clip(t, self.knots[0], self.knots[-1]) - self.knots[seg]
        c = self.coeffs[seg]  # (n, d, 6)
        k = np.arange(6)
        sk = s[:, None] ** k  # (n, 6)
        pos = np.einsum("ndk,nk->nd", c, sk)
        ds = np.zeros_like(sk)
        ds[:, 1:] = k[1:] * s[:, None] ** (k[1:] - 1)
        dds = np.zeros_like(sk)
        dds[:, 2:] = k[2:] * (k[2:] - 1) * s[:, None] ** (k[2:] - 2)
        outside = ((t < self.knots[0]) | (t > self.knots[-1]))[:, None]
        vel = np.where(outside, 0.0, np.einsum("ndk,nk->nd", c, ds))
        acc = np.where(outside, 0.0, np.einsum("ndk,nk->nd", c, dds))
        return Samples(t, pos[None], vel[None], acc[None])

    def shifted(self, start: float) -> PiecewiseQuintic:
        """The same motion starting at time ``start`` instead of ``knots[0]``."""
        return PiecewiseQuintic(self.knots - self.knots[0] + start, self.coeffs)

    def symbolic(self, t: Any, esym: Any, dim: int, derivative: int = 0) -> Any:
        """An ``exudyn.symbolic`` expression of coordinate ``dim`` (or its derivative) at ``t``.

        Built as a balanced tree of IfThenElse so the depth grows with log(segments).
        """
        m = len(self.coeffs)
        poly = []
        for seg in range(m):
            c = self.coeffs[seg, dim]
            deriv = [c[k] * _falling(k, derivative) for k in range(derivative, 6)]
            s = t - esym.Real(float(self.knots[seg]))
            expr = esym.Real(float(deriv[-1]))
            for coef in reversed(deriv[:-1]):  # Horner
                expr = expr * s + esym.Real(float(coef))
            poly.append(expr)
        hold_start = float(self.coeffs[0, dim, 0]) if derivative == 0 else 0.0
        end = self.sample(self.knots[-1:]).position[0, 0, dim] if derivative == 0 else 0.0
        inside = _tree(t, esym, self.knots, poly, 0, m)
        return esym.IfThenElse(
            t < esym.Real(float(self.knots[0])),
            esym.Real(hold_start),
            esym.IfThenElse(t > esym.Real(float(self.knots[-1])), esym.Real(float(end)), inside),
        )


def _falling(k: int, n: int) -> float:
    """k (k-1) ... (k-n+1): the factor d^n/ds^n s^k = falling(k, n) s^(k-n)."""
    out = 1.0
    for i in range(n):
        out *= k - i
    return out


def _tree(t: Any, esym: Any, knots: Array, poly: list[Any], lo: int, hi: int) -> Any:
    if hi - lo == 1:
        return poly[lo]
    mid = (lo + hi) // 2
    return esym.IfThenElse(
        t < esym.Real(float(knots[mid])),
        _tree(t, esym, knots, poly, lo, mid),
        _tree(t, esym, knots, poly, mid, hi),
    )
