"""The estimators of climbing_slip §4.1 on F_t = mu (F_n + F_adh): least squares and the
Kalman-filter-like estimator over windows of samples.

F_n is the normal load pressing the pad (compression positive), F_t the tangential force while
the pad slips, F_adh the adhesion force that friction sees as extra normal load.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]
PROCESS = (4e-6, 0.01)  # Q = diag(mu, F_adh), the seed's values
OBSERVATION = 0.25  # R per sample, N^2
WINDOW = 15  # samples per update


@dataclass(frozen=True)
class Estimate:
    mu: float
    adhesion: float  # N


def least_squares(fn: Array, ft: Array) -> Estimate:
    """F_t = mu F_n + c in closed form (the seed's FONC); F_adh = c / mu."""
    A = np.stack([fn, np.ones_like(fn)], axis=1)
    (mu, c), *_ = np.linalg.lstsq(A, ft, rcond=None)
    return Estimate(float(mu), float(c / mu))


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
    iterations: int = 5,
) -> Track:
    """The state (mu, F_adh) propagates as a random walk of covariance Q per window; each window
    of ``window`` samples observes F_t through h = mu (F_n + F_adh), linearised at the estimate
    with the measured F_n as the observation model: H_k = [F_n,k + F_adh, mu]. ``spread`` is the
    initial standard deviation of (mu, F_adh); samples past the last whole window are dropped.
    Each window's update re-linearises ``iterations`` times (an iterated EKF): with a single
    linearisation a start far from the truth leaves the filter stuck on the wrong branch of
    mu F_adh = const, which Q's small mu walk cannot leave (0.66 for 0.45 on the unit test)."""
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
        prior, x_k = x, x
        for _ in range(iterations):  # iterated linearisation: Gauss-Newton on the window
            H = np.stack([Fn[k] + x_k[1], np.full(window, x_k[0])], axis=1)
            y = Ft[k] - x_k[0] * (Fn[k] + x_k[1]) - H @ (prior - x_k)
            K = np.linalg.solve(H @ P @ H.T + R, H @ P).T
            x_k = prior + K @ y
        x = x_k
        P = (np.eye(2) - K @ H) @ P
        out[k] = x
    return Track(np.arange(1, n + 1) * window, out[:, 0], out[:, 1])
