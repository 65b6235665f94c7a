"""The strategy functions fs1..fs7 (FTFOF §V.A) and body jitter fsj, vectorised over a population.

Every function takes (pop, n) or (pop, n, d) arrays and returns (pop,). fs1, fs2, fs3, fs7 and
fsj read the surrogates' target series (predicted or simulated, defined in
:mod:`ftfof.data.targets`, each on its own window); fs4, fs5 and fs6 read the sampled trajectory.
fs1/fs2 read the resultant pull; fs1_normal/fs2_normal the tension alone, as the paper did.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from ftfof.config import Strategy

Array = NDArray[np.float64]

DETACHED_FRACTION = 0.05  # fs2: detachment is complete once Fd falls below 5 % of its peak
JITTER_SIGMAS = 3.0  # fs7: m, the z-score threshold


def fs1_max_detachment(Fd: Array) -> Array:
    """Peak detachment force (eq. 10), of the pull or of its normal part."""
    return np.max(Fd, axis=-1)


def fs2_mean_detachment(Fd: Array) -> Array:
    """Mean Fd from t = 0 to complete detachment (eq. 11).

    Complete detachment is the first sample after the peak where Fd drops below 5 % of the peak;
    if it never does, the window runs to the end of the series.
    """
    Fd = np.asarray(Fd, dtype=float)
    n = Fd.shape[-1]
    idx = np.arange(n)
    peak_at = np.argmax(Fd, axis=-1)[..., None]
    peak = np.take_along_axis(Fd, peak_at, axis=-1)
    below = (idx > peak_at) & (Fd < DETACHED_FRACTION * peak)
    end = np.where(below.any(axis=-1), np.argmax(below, axis=-1), n - 1)
    window = idx <= end[..., None]
    return np.sum(np.where(window, Fd, 0.0), axis=-1) / (end + 1)


def fs3_pre_pressure_error(Fp: Array, target: float) -> Array:
    """Distance of the peak (landing) pre-pressure from the optimal pre-pressure a (eq. 12)."""
    return np.abs(np.max(Fp, axis=-1) - target)


def fs4_mean_height(position: Array) -> Array:
    """Mean z of the trajectory samples (eq. 13)."""
    return np.mean(position[..., 1], axis=-1)


def fs5_adhesion_path_length(velocity: Array, t: Array, t_start: float, t_end: float) -> Array:
    """Path length over the adhesion segment, the integral of |B'(t)| over [T2, T3] (eq. 14).

    Trapezoidal rule over the samples inside the window (the grid should include T2 and T3 or be
    fine enough for the error to be negligible).
    """
    sel = np.flatnonzero((t >= t_start - 1e-12) & (t <= t_end + 1e-12))
    lo, hi = sel[0], sel[-1] + 1
    speed = np.sqrt(sum(velocity[..., lo:hi, k] ** 2 for k in range(velocity.shape[-1])))
    return np.trapezoid(speed, t[lo:hi], axis=-1)


def fs6_bending(position: Array, min_step: float) -> Array:
    """Sum of the turning angles above 90 degrees between consecutive displacements (eq. 15).

    Displacements shorter than ``min_step`` carry no direction (the ends, where the velocity is
    zero) and are skipped: each displacement is compared with the previous *kept* one, so a
    reversal through a standstill still counts. arccos(c) - pi/2 = arcsin(-c). Always >= 0.
    One compiled pass per trajectory: this runs on every candidate of every generation.
    """
    position = np.asarray(position, dtype=float)
    lead = position.shape[:-2]
    flat = position.reshape(-1, *position.shape[-2:])
    out = np.empty(flat.shape[0])
    _fs6_kernel(flat, float(min_step), out)
    return out.reshape(lead)


@numba.njit(cache=True, nogil=True)
def _fs6_kernel(pos: Array, min_step: float, out: Array) -> None:  # pragma: no cover - compiled
    pop, n, d = pos.shape
    cur = np.empty(d)
    prev = np.empty(d)
    for p in range(pop):
        total = 0.0
        prev_norm = -1.0
        for i in range(n - 1):
            norm2 = 0.0
            for k in range(d):
                cur[k] = pos[p, i + 1, k] - pos[p, i, k]
                norm2 += cur[k] * cur[k]
            norm = np.sqrt(norm2)
            if norm <= min_step:
                continue
            if prev_norm > 0.0:
                dot = 0.0
                for k in range(d):
                    dot += cur[k] * prev[k]
                c = dot / (norm * prev_norm)
                if c < 0.0:
                    total += np.arcsin(min(-c, 1.0))
            prev[:] = cur
            prev_norm = norm
        out[p] = total


def jitter_exceedance(F: Array, dt: float, m: float = JITTER_SIGMAS) -> Array:
    """Per sample, how far the z-score of F'' exceeds m standard deviations (eq. 16's terms).

    A flat second derivative (sigma = 0) has no outliers and scores 0.
    """
    acc = np.gradient(np.gradient(np.asarray(F, dtype=float), dt, axis=-1), dt, axis=-1)
    mu = acc.mean(axis=-1, keepdims=True)
    sigma = acc.std(axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        z = np.where(sigma > 0, (acc - mu) / sigma, 0.0)
    return np.maximum(np.abs(z) - m, 0.0)


def fs7_jitter(running: Array) -> Array:
    """eq. 16: the sum of the exceedances, given as their running total over time (the
    ``jitter`` target), so the total is its maximum."""
    return np.max(running, axis=-1)


def fsj_body_jitter(body_acc: Array) -> Array:
    """Peak body acceleration during detachment (the IMU jitter of FTFOF Table I)."""
    return np.max(body_acc, axis=-1)


def film_safety(curvature: Array, min_bend_radius: float) -> Array:
    """fc * max curvature - 1: <= 0 when the film never bends tighter than fc."""
    return min_bend_radius * np.max(curvature, axis=-1) - 1.0


def pad_clearance(clearance: Array, required: float) -> Array:
    """1 - max clearance / required: <= 0 when the whole pad rises ``required`` above the wall."""
    return 1.0 - np.max(clearance, axis=-1) / required


def pad_retouch(retouch: Array, allowed: float) -> Array:
    """max re-formed bonds in the swing / allowed - 1: <= 0 when the pad, once off, is expected to
    stay off the wall until the landing segment (the retouch target's values are 0 or whole
    bonds, so a prediction is the expected count where the outcome is uncertain: 0.5 allowed
    means more likely than not none)."""
    return np.max(retouch, axis=-1) / allowed - 1.0


def pad_holds(holds: Array) -> Array:
    """1 - max verdict / 0.5: <= 0 when the landed pad more likely than not holds the proof pull
    (the holds target is 1 where it held, 0 where it let go, so a prediction is the chance)."""
    return 1.0 - np.max(holds, axis=-1) / 0.5


@dataclass(frozen=True)
class Evidence:
    """What the strategy functions read for one population.

    ``series``: target name (:data:`ftfof.data.targets.TARGETS`) -> (pop, n) series, predicted or
    simulated, on one uniform time base of step ``dt``; the foot path sampled on its own grid
    ``t`` over [0, T3]; the adhesion segment [T2, T3]; the pre-pressure a.
    """

    series: Mapping[str, Array]
    dt: float
    position: Array
    velocity: Array
    t: Array
    adhesion: tuple[float, float]
    pre_pressure: float
    min_step: float = 1e-9

    def __getitem__(self, name: str) -> Array:
        if name not in self.series:
            raise KeyError(f"no {name!r} series in the evidence (have {sorted(self.series)})")
        return self.series[name]


# One entry per name of config.Strategy (a test holds them equal).
STRATEGIES: dict[Strategy, Callable[[Evidence], Array]] = {
    "fs1": lambda e: fs1_max_detachment(e["pull"]),
    "fs1_normal": lambda e: fs1_max_detachment(e["Fd"]),
    "fs2": lambda e: fs2_mean_detachment(e["pull"]),
    "fs2_normal": lambda e: fs2_mean_detachment(e["Fd"]),
    "fs3": lambda e: fs3_pre_pressure_error(e["Fp"], e.pre_pressure),
    "fs4": lambda e: fs4_mean_height(e.position),
    "fs5": lambda e: fs5_adhesion_path_length(e.velocity, e.t, *e.adhesion),
    "fs6": lambda e: fs6_bending(e.position, e.min_step),
    "fs7": lambda e: fs7_jitter(e["jitter"]),
    "fsj": lambda e: fsj_body_jitter(e["body_acc"]),
}


def strategy_values(names: Sequence[str], evidence: Evidence) -> Array:
    """(pop, len(names)) values of the named strategy functions, columns in the given order."""
    unknown = [n for n in names if n not in STRATEGIES]
    if unknown:
        raise ValueError(f"unknown strategy functions {unknown} (have {sorted(STRATEGIES)})")
    return np.column_stack([STRATEGIES[n](evidence) for n in names])
