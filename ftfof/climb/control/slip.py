"""A stance foot that slips: its detection (climbing_slip §6.2), its slip rate and the QP weight
adaptation that answers it (§5), and the estimate of its pad's mu and F_adh (§4.1).

Signs as in :mod:`ftfof.climb.control.forces`: a foot's tangential velocity and force along +x
(up the wall), f_n > 0 pressing into the wall; the QP weights are W_f's diagonal per foot,
(tangential, normal).

Our reading of the paper, whose equations are images:

- Detection (§6.2, Fig. 6A): "once the contact velocity exceeds the threshold during the certain
  amount of time, we declare the slip detection". A stance foot slips once its tangential speed
  has stayed above ``threshold`` for ``hold`` seconds; one step at or below it starts the count
  again, and so does leaving the stance.
- Slip rate (§5.1): defined from the slip velocity with a threshold, so that the weights change
  "only if the slippage is large enough" while "the rate parameter itself is continuous". We take
  rho = tanh(max(|v| - v_th, 0) / span): 0 up to the threshold, continuous there, smooth and
  rising above it, saturating at 1 (a fast slide cannot drive the weights without bound).
- Weight adaptation (§5.2, and the contributions: "we increase the normal contact force and
  decrease the tangential force by regulating the weights for ground reaction force"): the QP
  minimises the weighted forces, so to move load toward the normal the slipping foot's
  tangential weight goes up and its normal weight down, by one factor alpha = max_factor**rho:
  W_t <- alpha W_t, W_n <- W_n / alpha. The paper's nominal weights put the normal one far below
  the tangential; the update keeps the other feet's weights. On a wall the feet's normal forces
  sum to about zero, so a freer normal force lets the slipping foot take more of the trunk's
  moment, whatever its sign (a fore foot pulls more, a hind foot presses more), while its shear
  goes to the others; it cannot press a fore foot without pulling its partner.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from ftfof.identify.estimate import Estimate, kalman, least_squares

Array = NDArray[np.float64]
CLOCK = 1e-12  # s: a hold summed from float steps may fall short of itself by a few ulps
MAX_FACTOR = 400.0  # alpha at a saturated slip: the weights move by at most 400x each way


@dataclass
class SlipDetector:
    """Per-foot slip detection, updated once per control step (vectorised over the feet)."""

    threshold: float  # m/s: a stance foot's tangential speed above this may be a slip
    hold: float  # s: how long the speed must stay above it before the slip is declared
    feet: int = 4
    elapsed: Array = field(init=False)  # s each foot's speed has been above the threshold

    def __post_init__(self) -> None:
        if self.threshold < 0 or self.hold < 0:
            raise ValueError("the slip threshold and hold time must be non-negative")
        self.elapsed = np.zeros(self.feet)

    def update(self, velocity: Array, stance: Array, dt: float) -> Array:
        """Which feet slip after this step: ``velocity`` the feet's tangential velocities (m/s),
        ``stance`` which feet are on the wall, ``dt`` the step (s)."""
        fast = np.asarray(stance, dtype=bool) & (np.abs(velocity) > self.threshold)
        self.elapsed = np.where(fast, self.elapsed + dt, 0.0)
        return self.slipping

    @property
    def slipping(self) -> Array:
        return self.elapsed + CLOCK >= self.hold

    def reset(self) -> None:
        """Forget every count (a new phase: the paper's controller starts its weights anew)."""
        self.elapsed = np.zeros(self.feet)


def slip_rate(velocity: Array, threshold: float, span: float) -> Array:
    """rho in [0, 1) per foot: 0 up to ``threshold`` (m/s), tanh of the excess speed over
    ``span`` (m/s) above it."""
    excess = np.maximum(np.abs(np.asarray(velocity, dtype=float)) - threshold, 0.0)
    return np.tanh(excess / span)


def adapt_weights(nominal: Array, rate: Array, max_factor: float = MAX_FACTOR) -> Array:
    """The feet's QP weights (n, 2: tangential, normal) under slip rates ``rate`` (n,): each
    foot's tangential weight times alpha = max_factor**rate, its normal weight over alpha, so the
    QP hands a slipping foot more pressing and less shear. A rate of 0 leaves the foot nominal."""
    alpha = max_factor ** np.asarray(rate, dtype=float)
    out = np.array(nominal, dtype=float)
    out[:, 0] *= alpha
    out[:, 1] /= alpha
    return out


def fit_pad(
    fn: Array,
    ft: Array,
    method: Literal["kalman", "least_squares"] = "kalman",
    prior: Estimate | None = None,
) -> Estimate:
    """mu and F_adh of a slipping foot's pad from a window of its measured forces, in the slip
    law's tangential form F_t = mu F_n + F_adh (:mod:`ftfof.identify.estimate`), F_adh in newtons
    of shear as ``identify`` reports it. While it slides, the pad's friction is at its limit
    whichever way it slides, so |f_t| is what that law sees. ``prior`` is where the Kalman
    estimator starts, in the controller's cone form (the pad's assumed mu and cone shift F_adh /
    mu); least squares needs none."""
    fn = np.asarray(fn, dtype=float)
    ft = np.abs(np.asarray(ft, dtype=float))
    if method == "least_squares":
        return least_squares(fn, ft)
    if method != "kalman":
        raise ValueError(f"unknown estimator {method!r}: kalman or least_squares")
    if prior is None:
        raise ValueError("the Kalman estimator starts from a prior: the pad's assumed mu, F_adh")
    return kalman(fn, ft, Estimate(prior.mu, prior.mu * prior.adhesion)).final


def cone_of(fit: Estimate) -> Estimate:
    """A tangential-form fit (:func:`fit_pad`) as the controller's cone takes it: mu and the
    shift of mu (F_n + F_adh), F_adh / mu."""
    shift = fit.adhesion / fit.mu if fit.mu != 0 else math.copysign(math.inf, fit.adhesion)
    return Estimate(fit.mu, shift)


def estimate_adhesion(fn: Array, ft: Array, mu: float) -> float:
    """F_adh of a sliding pad whose mu is taken as known: each sample sits on the cone's edge,
    |f_t| = mu (f_n + F_adh), so F_adh = mean(|f_t| / mu - f_n). This is what is left to estimate
    when the two-parameter fit is off the physical range: a pad that loses its bonds while it
    slides holds ever less shear as its pull eases, f_t and f_n fall together, and the fit's
    slope, mu, comes out negative (FR's slide before it lets go, issue 40)."""
    if mu <= 0:
        raise ValueError(f"the adhesion estimate needs a positive mu, got {mu}")
    fn = np.asarray(fn, dtype=float)
    return float(np.mean(np.abs(np.asarray(ft, dtype=float)) / mu - fn))
