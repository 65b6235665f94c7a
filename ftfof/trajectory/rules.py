"""Rules on the whole sampled trajectory that a control-point bound cannot express.

Each function maps a population's samples (pop, n_t, d) to a (pop,) violation, > 0 violated,
vectorised over rows and times, and dimension-agnostic where it costs nothing.

- :func:`md_path_violation`: the minimum detachment point md = (ld, hd) holds on the *path*
  (FTFOF §III.B.3, §VI.A.3): while detaching, the foot is at least hd off the wall once it has
  moved ld along it. A bound on P5 alone lets the foot crawl along the wall.
- :func:`path_radius_violation` and :func:`reversal_violation`: fs6 (eq. 15) that a hairpin cannot
  slip through. fs6 compares displacement directions between samples, so it shrinks to zero for
  any smooth path as sampling gets denser, and a hairpin whose turn falls between samples passes
  (the first full run's optimum had a 0.3 mm swing apex that passed on 256 samples and failed on
  31 or 64). Instead the path's curvature radius |v|^3 / |v x a| is read from the analytic Bezier
  velocity and acceleration at each sample: a pointwise property of the curve, not a difference
  that depends on the spacing. A hairpin tighter than the spacing leaves no sample at its apex, but
  then the tangent turns by more than 90 degrees between neighbouring samples; that velocity
  reversal is the second rule. Together they hold whatever the sampling density.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def md_path_violation(position: Array, t: Array, t_detach: float, ld: float, hd: float) -> Array:
    """Depth of the deepest detachment sample inside the forbidden quadrant x > ld, z < hd.

    min(x - ld, hd - z) is > 0 exactly when a point is in that quadrant and is continuous in the
    decision variables (a point entering the quadrant at x = ld starts at depth 0), so the
    optimiser sees a measure that grows smoothly instead of jumping by hd - z at x = ld.
    """
    detach = np.asarray(t) <= t_detach
    x, z = position[..., detach, 0], position[..., detach, -1]
    return np.max(np.minimum(x - ld, hd - z), axis=-1)


def curvature_radius(velocity: Array, acceleration: Array) -> Array:
    """|v|^3 / |v x a| per sample (pop, n_t); 0 where the foot stops, inf on a straight line.

    |v x a|^2 = |v|^2 |a|^2 - (v.a)^2 (Lagrange's identity) works in any dimension.
    """
    vv = np.einsum("...k,...k->...", velocity, velocity)
    aa = np.einsum("...k,...k->...", acceleration, acceleration)
    va = np.einsum("...k,...k->...", velocity, acceleration)
    cross = np.sqrt(np.maximum(vv * aa - va * va, 0.0))
    speed3 = vv * np.sqrt(vv)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(speed3 > 0, speed3 / cross, 0.0)


def path_radius_violation(
    velocity: Array, acceleration: Array, t: Array, min_radius: float
) -> Array:
    """max over judged samples of 1 - radius / min_radius, at least 0; in [0, 1].

    Both ends start and stop with zero velocity and acceleration (eq. 6), where the radius of
    every such curve tends to zero over a few tenths of a millimetre of path (the published
    MST-M3F optimum: < 0.2 mm). A path that short cannot fold back at min_radius, so samples
    within one min_radius of path from either end are not judged; the reversal rule still is.
    """
    radius = curvature_radius(velocity, acceleration)
    speed = np.sqrt(np.einsum("...k,...k->...", velocity, velocity))
    step = 0.5 * (speed[..., 1:] + speed[..., :-1]) * np.diff(t)
    arc = np.concatenate([np.zeros((*speed.shape[:-1], 1)), np.cumsum(step, axis=-1)], axis=-1)
    judged = (arc >= min_radius) & (arc[..., -1:] - arc >= min_radius)
    shortfall = np.where(judged, 1.0 - np.minimum(radius / min_radius, 1.0), 0.0)
    return np.max(shortfall, axis=-1)


def reversal_violation(velocity: Array, min_speed: float) -> Array:
    """max over neighbouring samples of -cos(turn between their velocities); > 0 past 90 deg.

    Samples slower than ``min_speed`` carry no direction (the ends) and are left out of the
    pairs they belong to; a stop exactly on a sample mid-path has radius 0 and is the radius
    rule's to catch.
    """
    speed = np.sqrt(np.einsum("...k,...k->...", velocity, velocity))
    moving = speed > min_speed
    dot = np.einsum("...k,...k->...", velocity[..., 1:, :], velocity[..., :-1, :])
    pair = moving[..., 1:] & moving[..., :-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        cos = np.where(pair, dot / (speed[..., 1:] * speed[..., :-1]), 1.0)
    return np.max(-cos, axis=-1)
