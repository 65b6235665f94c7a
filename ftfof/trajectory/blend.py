"""The minimum-jerk blend: how the gait moves the body and lays a landed foot's press off, and
how the slip and hold tests ramp their loads (one home for all of them)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]


def min_jerk(s: ArrayLike) -> tuple[Array, Array]:
    """The minimum-jerk blend of s in [0, 1] (clipped) and its derivative d/ds."""
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10 - 15 * s + 6 * s * s), 30 * s * s * (1 - s) ** 2
