"""The redundancy hierarchical strategy: one trajectory from a Pareto front (FTFOF Algorithm 1).

Objectives are visited in priority order, cyclically; each visit keeps the rows within a shrinking
fraction alpha of that objective's remaining range above its minimum, and alpha shrinks by
beta^k after the k-th visit. The row holding the minimum always survives, so the set is never
empty. A constant column keeps every row; when alpha underflows with several rows left (ties),
the lexicographic minimum in priority order wins, then the lowest row index
(FTFOF Algorithm 1, §V.C).

An optional ``resolution`` per objective widens each cut to at least the minimum plus it:
differences smaller than what the objective can be measured to (the simulator's repeatability)
do not cut, and the next priority does. Rows still left when alpha underflows (within the
resolution on every objective) go to the lexicographic rule on their values, as exact ties do.
Without it the algorithm is exactly the paper's.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

ALPHA_FLOOR = 1e-9


@dataclass(frozen=True)
class RHSStep:
    """One visit: the objective column, its range over the remaining rows, the cut and survivors."""

    objective: int
    low: float
    high: float
    cut: float
    alpha: float
    remaining: tuple[int, ...]

    def as_dict(self) -> dict:
        return {
            "objective": self.objective,
            "min": self.low,
            "max": self.high,
            "cut": self.cut,
            "alpha": self.alpha,
            "remaining": list(self.remaining),
        }


@dataclass(frozen=True)
class RHSResult:
    index: int
    steps: tuple[RHSStep, ...]
    tie_break: bool  # True when the loop ended with several rows and the lexicographic rule chose
    resolution: tuple[float, ...] = ()  # per objective, as given (empty: none)


def rhs_trace(
    F: ArrayLike,
    priority: Sequence[int],
    alpha: float = 0.9,
    beta: float = 0.9,
    resolution: ArrayLike | None = None,
) -> RHSResult:
    """Algorithm 1 on the minimisation front ``F`` (rows = solutions), with its full trace;
    ``resolution`` (one value >= 0 per column of ``F``) makes smaller differences ties."""
    F = _validated(F, priority, alpha, beta)
    ties = np.zeros(F.shape[1]) if resolution is None else np.asarray(resolution, dtype=float)
    if ties.shape != (F.shape[1],) or not np.all(ties >= 0):
        raise ValueError(f"resolution must be {F.shape[1]} values >= 0, got {ties.tolist()}")
    rows = np.arange(F.shape[0])
    steps: list[RHSStep] = []
    k = 0
    while rows.size > 1:
        i = int(priority[k % len(priority)])
        column = F[rows, i]
        low, high = float(column.min()), float(column.max())
        cut = max(low + (high - low) * alpha, low + ties[i])
        rows = rows[column <= cut]
        steps.append(RHSStep(i, low, high, cut, alpha, tuple(int(r) for r in rows)))
        alpha *= beta**k
        k += 1
        if alpha < ALPHA_FLOOR:
            break
    tie_break = rows.size > 1
    if tie_break:
        keys = [F[rows, int(i)] for i in reversed(priority)]  # lexsort: last key is primary
        rows = rows[np.lexsort([rows, *keys])]
    given = () if resolution is None else tuple(float(r) for r in ties)
    return RHSResult(int(rows[0]), tuple(steps), tie_break, given)


def _validated(
    F: ArrayLike, priority: Sequence[int], alpha: float, beta: float
) -> NDArray[np.float64]:
    F = np.asarray(F, dtype=float)
    if F.ndim != 2 or F.shape[0] == 0:
        raise ValueError(f"F must be a non-empty (rows, objectives) array, got shape {F.shape}")
    if not np.all(np.isfinite(F)):
        raise ValueError("F holds NaN or infinite objective values")
    if len(priority) == 0 or any(not 0 <= int(i) < F.shape[1] for i in priority):
        raise ValueError(f"priority {list(priority)} must index the {F.shape[1]} columns of F")
    if not 0 < alpha <= 1:
        raise ValueError(f"alpha must lie in (0, 1], got {alpha}")
    if not 0 < beta < 1:  # beta = 1 never shrinks alpha: ties would loop forever
        raise ValueError(f"beta must lie in (0, 1), got {beta}")
    return F
