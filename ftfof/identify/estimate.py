"""The estimators of climbing_slip §4.1 on the slip law F_t = mu F_n + F_adh: least squares and
the Kalman-filter-like estimator over windows of samples.

F_n is the normal load pressing the pad (compression positive), F_t the peak tangential force of
a slip, F_adh the adhesion's share of it, a force along the slip (docs/decisions/0027): the pad's
bonds hold F_adh whatever the load, friction adds mu F_n. climbing_slip writes the same line as
mu (F_n + F_adh'), a cone shifted by F_adh' = F_adh / mu (the climbing controller's form,
:mod:`ftfof.climb.control.slip`); the tangential form keeps the adhesion in newtons of shear, and
the line is linear in (mu, F_adh), so the filter needs no linearisation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]
# Q = diag(mu, F_adh): the seed's values, its F_adh walk carried from the cone's shift to the
# tangential form (times mu^2, mu about 0.45)
PROCESS = (4e-6, 0.002)
OBSERVATION = 0.25  # R per sample, N^2
WINDOW = 15  # samples per update


@dataclass(frozen=True)
class Estimate:
    mu: float
    adhesion: float  # N


def least_squares(fn: Array, ft: Array) -> Estimate:
    """F_t = mu F_n + F_adh in closed form (the seed's FONC)."""
    A = np.stack([fn, np.ones_like(fn)], axis=1)
    (mu, adhesion), *_ = np.linalg.lstsq(A, ft, rcond=None)
    return Estimate(float(mu), float(adhesion))


@dataclass(frozen=True)
class Track:
    """The Kalman estimate after each window, for the convergence plot."""

    samples: NDArray[np.int64]  # samples seen after each window
    mu: Array
    adhesion: Array

    @property
    def final(self) -> Estimate:
        return Estimate(float(self.mu[-1]), float(self.adhesion[-1]))


def kalman(
    fn: Array,
    ft: Array,
    start: Estimate,
    window: int = WINDOW,
    process: tuple[float, float] = PROCESS,
    observation: float = OBSERVATION,
    spread: tuple[float, float] = (1.0, 100.0),
) -> Track:
    """The state (mu, F_adh) propagates as a random walk of covariance Q per window; each window
    of ``window`` samples observes F_t = mu F_n + F_adh, H_k = [F_n,k, 1], linear in the state,
    so one update per window is exact. ``spread`` is the initial standard deviation of
    (mu, F_adh); samples past the last whole window are dropped."""
    n = fn.size // window
    if n == 0:
        raise ValueError(f"the Kalman estimator needs at least {window} samples, got {fn.size}")
    Fn = fn[: n * window].reshape(n, window)
    Ft = ft[: n * window].reshape(n, window)
    x = np.array([start.mu, start.adhesion], dtype=float)
    P = np.diag(np.square(spread)).astype(float)
    Q = np.diag(process)
    R = observation * np.eye(window)
    out = np.empty((n, 2))
    for k in range(n):
        P = P + Q
        H = np.stack([Fn[k], np.ones(window)], axis=1)
        K = np.linalg.solve(H @ P @ H.T + R, H @ P).T
        x = x + K @ (Ft[k] - H @ x)
        P = (np.eye(2) - K @ H) @ P
        out[k] = x
    return Track(np.arange(1, n + 1) * window, out[:, 0], out[:, 1])
