"""Heavy tails of the surrogates' targets, compressed before any model is fitted to them.

A few sampled trajectories do not let go or land hard: their pull runs to 80 N where the median
is 7.7 N, their landing press to 156 N where it is 5.0 N, their body acceleration to 207 m/s²
where it is 13. Squared errors on such rows set the GRU's loss and a GP's amplitude and noise,
and the fit of the bulk, where the front lies, is what is left over (the landing-press GP fitted
from scratch explained nothing: all noise; the GRU's pull ranked the validation split at 0.43 to
0.71 by seed). Above Tukey's far-out fence, Q3 + k IQR of the training rows' peaks, a value is
compressed to fence + IQR log(1 + excess / IQR): the identity up to the fence, continuous with
slope 1 there, monotone and exactly invertible, so an outlier stays the largest value and a
model's prediction maps back to the target's unit (docs/decisions/0041-tamed-target-tails.md).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]
MAX_EXCESS = 30.0  # compressed spreads above the fence that untame still maps exactly


def fence(peaks: Array, k: float) -> tuple[float, float]:
    """(fence, spread) of the finite ``peaks``: Q3 + ``k`` IQR and the IQR; a spread of 0 (no
    spread, no peaks, or ``k`` 0) leaves the values as they are."""
    finite = np.asarray(peaks, dtype=float)
    finite = finite[np.isfinite(finite)]
    if k <= 0 or finite.size == 0:
        return 0.0, 0.0
    q1, q3 = np.percentile(finite, [25, 75])
    spread = float(q3 - q1)
    return (float(q3 + k * spread), spread) if spread > 0 else (0.0, 0.0)


def tame(y: Array, upper: float, spread: float) -> Array:
    """A copy of ``y`` with the values above ``upper`` compressed logarithmically on the scale
    ``spread`` (NaN stays NaN)."""
    return _mapped(y, upper, spread, np.log1p)


def untame(g: Array, upper: float, spread: float) -> Array:
    """The inverse of :func:`tame`. A model's prediction far past anything it was fitted on maps
    to a large finite value, not an overflow: its compressed excess is capped at MAX_EXCESS
    (e^30 spreads above the fence; the optimiser refused an infinite objective)."""
    return _mapped(g, upper, spread, lambda x: np.expm1(np.minimum(x, MAX_EXCESS)))


def _mapped(values: Array, upper: float, spread: float, excess: Callable[[Array], Array]) -> Array:
    """A copy of ``values``, those above ``upper`` at upper + spread f((value - upper) / spread):
    only they are computed (the optimiser maps every predicted series, few of them are over)."""
    out = np.array(values, dtype=float)
    if spread > 0:
        over = out > upper
        out[over] = upper + spread * excess((out[over] - upper) / spread)
    return out
