"""Gaussian-process models of a target's peak, straight from the trajectory's control values.

Two objectives read one number of a series: fs3 the landing press's peak (max ``Fp``) and fs7
eq. 16's total (max of the ``jitter`` running sum). The GRU predicts the whole series, and its
maximum carries the series model's error at every step. A GP with one length scale per control
value (ARD) learns the number itself from the 12 values that fix the trajectory, and learns which
of them matter (the landing press: the adhesion segment's last control points). On the paper-scale
acquisition's validation split it predicts the landing peak to 0.035 N median (GRU: 0.11 N) and
fs7 to 1.9 (GRU: 4.2); docs/surrogates.md has the table. It is no better on the pull or the body
acceleration, which keep the GRU's.

The surrogate keeps the GRU's series shape and scales it to the GP's peak
(:meth:`ftfof.surrogate.predict.Surrogate.predict`), so every reader of the series (the objective,
the landing constraint, the report's plots) sees one prediction.

Near the front, one GP over the whole design is not enough for the landing press: a stationary
kernel fitted on 850 trajectories spread over the box misses the fine structure where the
optimiser searches (landing-press error 0.08-0.12 N on the next round's points, 3x the
validation split's). :class:`NearFront` adds a second GP fitted on the refinement rounds' points
alone and takes it where it knows the trajectory, the broad GP elsewhere (docs/surrogates.md).
The same holds for the body's acceleration (fsj), which has no broad GP: there the local GP is
blended with the GRU's own maximum, and fitted on log(peak) (Spearman on one run's last round
0.54 -> 0.84).

Fitting uses scikit-learn's ``GaussianProcessRegressor`` (hyperparameters by maximum marginal
likelihood); the fitted model is kept as plain arrays (no pickle) and predicts in NumPy, a
(pop, n_train) kernel product per population. Refinement refits it on the grown data with the
hyperparameters it has (a solve, no search), so the rounds' new rows count at once.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, fields, replace

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import cho_factor, cho_solve

from ftfof.data.tails import tame, untame

Array = NDArray[np.float64]

JITTER = 1e-10  # scikit-learn's default ``alpha``: added to the kernel's diagonal in a fit


@dataclass(frozen=True)
class PeakModel:
    """A fitted GP: control values (pop, d) -> the peak of one target (pop,), >= 0."""

    target: str
    input_mean: Array  # (d,)
    input_scale: Array  # (d,)
    length_scale: Array  # (d,), per normalised control value
    amplitude: float  # signal variance, in normalised target units
    noise: float  # white-noise variance, in normalised target units
    y_mean: float
    y_scale: float
    train_inputs: Array = field(repr=False)  # normalised, (n, d)
    weights: Array = field(repr=False)  # ((K + noise I)^-1 y, 1): the last multiplies the mean
    log: bool = False  # fitted on log(peak): predictions exp(GP), never below zero
    floor: float = 0.0  # no prediction below this (the smallest peak a local GP was fitted on)
    tail: tuple[float, float] = (0.0, 0.0)  # (fence, spread): peaks tamed before the fit

    def __call__(self, decisions: Array, series_peak: Array | None = None) -> Array:
        """The peaks; ``series_peak`` (the series model's maximum) is not needed here."""
        fitted = self._kernel(self._scaled(decisions)) @ self.weights
        peak = untame(np.exp(fitted) if self.log else fitted, *self.tail)
        return np.maximum(peak, self.floor)

    def _scaled(self, decisions: Array) -> Array:
        X = np.atleast_2d(np.asarray(decisions, dtype=float))
        if X.shape[-1] != self.input_mean.size:
            raise ValueError(
                f"the {self.target} peak model takes {self.input_mean.size} control values, "
                f"got {X.shape[-1]}"
            )
        return (X - self.input_mean) / self.input_scale

    def _kernel(self, scaled: Array) -> Array:
        """y_scale x the covariance with the training inputs, and a column of the mean:
        ``@ weights`` is the prediction in the target's unit."""
        k = self._covariance(scaled, self.train_inputs)
        return np.column_stack([k * self.y_scale, np.full(len(scaled), self.y_mean)])

    def _covariance(self, a: Array, b: Array) -> Array:
        """amplitude x the ARD RBF between normalised rows ``a`` and ``b``."""
        a, b = a / self.length_scale, b / self.length_scale
        d2 = (a**2).sum(-1)[:, None] + (b**2).sum(-1)[None, :] - 2.0 * a @ b.T
        return self.amplitude * np.exp(-0.5 * np.maximum(d2, 0.0))

    def refit(self, decisions: Array, peaks: Array) -> PeakModel:
        """The same GP (length scales, amplitude, noise, normalisation, floor) on other data: its
        rows with a finite (for a log model, positive) peak."""
        X = self._scaled(decisions)
        y = (_fitted(peaks, self.log, self.tail) - self.y_mean) / self.y_scale
        keep = _usable(X, y)
        X, y = X[keep], y[keep]
        K = self._covariance(X, X)
        K[np.diag_indices_from(K)] += self.noise + JITTER
        alpha = cho_solve(cho_factor(K, lower=True), y)
        return self._on(X, alpha)

    def _on(self, X: Array, alpha: Array) -> PeakModel:
        """This GP's hyperparameters on normalised training inputs ``X`` with weights ``alpha``."""
        return replace(self, train_inputs=X, weights=np.append(alpha, 1.0))

    def as_dict(self) -> dict:
        """JSON-ready: arrays as (nested) lists."""
        return {
            f.name: v.tolist() if isinstance(v := getattr(self, f.name), np.ndarray) else v
            for f in fields(self)
        }

    @classmethod
    def from_dict(cls, data: dict) -> PeakModel:
        scalars = ("target", "amplitude", "noise", "y_mean", "y_scale", "log", "floor", "tail")
        data = {**data, "tail": tuple(data.get("tail", (0.0, 0.0)))}
        return cls(
            **{
                k: v
                if k in scalars
                else np.asarray(v, dtype=float).reshape(
                    (-1, len(data["input_mean"])) if k == "train_inputs" else -1
                )
                for k, v in data.items()
            }
        )


@dataclass(frozen=True)
class NearFront:
    """A broad peak model (the whole design) and a local GP fitted on the refinement rounds'
    points alone, blended by how much the local GP knows: w = 1 - its posterior variance / its
    prior variance (near 1 on the rounds' points, 0 far from them), prediction
    w local + (1 - w) broad. So the optimiser, wandering off the region the rounds simulated,
    meets the broad model there and not the local one's prior mean.

    The broad model is a GP of the peak where ``train.peaks`` has one, else (``broad`` None) the
    series model's own maximum, which the caller passes: the body's acceleration, whose GP over
    the whole design predicts worse than the GRU (docs/surrogates.md)."""

    broad: PeakModel | None
    local: PeakModel
    local_precision: Array = field(repr=False)  # (K + noise I)^-1 of the local GP, normalised

    @property
    def target(self) -> str:
        return self.local.target

    @property
    def length_scale(self) -> Array:
        return (self.broad or self.local).length_scale

    def __call__(self, decisions: Array, series_peak: Array | None = None) -> Array:
        if self.broad is not None:
            broad = self.broad(decisions)
        elif series_peak is None:
            raise ValueError(
                f"the {self.target} near-front model blends with the series model's maximum: "
                "pass series_peak"
            )
        else:
            broad = np.asarray(series_peak, dtype=float)
        w = self.confidence(decisions)
        return w * self.local(decisions) + (1.0 - w) * broad

    def confidence(self, decisions: Array) -> Array:
        """(pop,) the share of the local GP's prior variance its data explain, in [0, 1]."""
        local = self.local
        k = local._covariance(local._scaled(decisions), local.train_inputs)
        explained = ((k @ self.local_precision) * k).sum(axis=1)
        return np.clip(explained / local.amplitude, 0.0, 1.0)

    def as_dict(self) -> dict:
        return {
            "broad": None if self.broad is None else self.broad.as_dict(),
            "local": self.local.as_dict(),
            "local_precision": self.local_precision.tolist(),
        }

    @classmethod
    def from_dict(cls, data: dict) -> NearFront:
        local = PeakModel.from_dict(data["local"])
        n = len(local.train_inputs)
        precision = np.asarray(data["local_precision"], dtype=float).reshape(n, n)
        broad = None if data["broad"] is None else PeakModel.from_dict(data["broad"])
        return cls(broad, local, precision)


PeakPredictor = PeakModel | NearFront


def peak_model_from_dict(data: dict) -> PeakPredictor:
    """A peak model as :meth:`as_dict` wrote it (either kind)."""
    return NearFront.from_dict(data) if "local" in data else PeakModel.from_dict(data)


# Local GPs of these peaks are fitted on log(peak). The body's peak acceleration spans 0.4-11 m/s²
# over the rounds' rows; fitted as it is, the local GP dipped below zero between them (clipped:
# fsj 0 at w = 1), and the search found those dips (fronts predicted 0.002-0.02 m/s², where the
# simulator read 0.55-0.82). In log space no such dip goes below a fraction of its neighbours, and
# the confidence w stays local (w > 0.5 on 6-10 % of feasible draws, against 24-43 % unlogged).
LOG_PEAKS = frozenset({"body_acc"})

# The local GP's longest length scale, in standard deviations of the rounds' control values. Left
# at the broad GP's 1e5, a value the rounds' peaks ignore ("irrelevant") made the confidence blind
# to distance along it: half of the sampled set, 4-6 local deviations from every rounds' point,
# got w > 0.5 and the blend erred 1.1-1.8x the broad GP there. At 5 a value spanning the rounds'
# points (+-2 deviations) still barely matters, and w falls off past them: w > 0.5 on 3-5 % of
# the sampled set, its error there within 2 % of the broad GP's, the next round's fs3 rho
# 0.87 / 0.76 / 0.77 against 0.67 / 0.70 / 0.69 uncapped (docs/surrogates.md).
LOCAL_MAX_LENGTH_SCALE = 5.0


def near_front(
    target: str,
    broad: PeakModel | None,
    decisions: Array,
    peaks: Array,
    tail: tuple[float, float] = (0.0, 0.0),
) -> NearFront:
    """``broad`` (None: the series model's maximum) with a local GP of ``target``'s peak fitted
    (hyperparameters by maximum likelihood, length scales at most
    :data:`LOCAL_MAX_LENGTH_SCALE`; on log(peak) for :data:`LOG_PEAKS`) on the refinement
    rounds' ``decisions`` and ``peaks`` (their ``tail`` tamed). It predicts no peak below the
    smallest of those: a dip between the rounds' points is the GP's, not the simulator's."""
    log = target in LOG_PEAKS
    local = fit_peak_model(target, decisions, peaks, LOCAL_MAX_LENGTH_SCALE, log, tail)
    fitted = _usable(np.asarray(decisions, dtype=float), _fitted(peaks, log, tail))
    local = replace(local, floor=float(np.asarray(peaks, dtype=float)[fitted].min()))
    K = local._covariance(local.train_inputs, local.train_inputs)
    K[np.diag_indices_from(K)] += local.noise + JITTER
    precision = cho_solve(cho_factor(K, lower=True), np.eye(len(K)))
    # C order, as a saved model loads it: the same sums in the same order, fresh or resumed
    return NearFront(broad, local, np.ascontiguousarray(precision))


def peak_kernel(d: int, max_length_scale: float = 1e5):
    """constant x ARD RBF + white noise over ``d`` standardised control values, on a target
    standardised to mean 0 and variance 1: the start (1, 1 each, 0.01) and the bounds."""
    from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

    signal = ConstantKernel(1.0, (1e-3, 1e3)) * RBF(np.ones(d), (1e-2, max_length_scale))
    return signal + WhiteKernel(1e-2, (1e-6, 1.0))


def _fitted(peaks: Array, log: bool, tail: tuple[float, float] = (0.0, 0.0)) -> Array:
    """What a GP of these peaks is fitted on: the peaks with their ``tail`` tamed
    (:mod:`ftfof.data.tails`), or the logarithm of those (NaN at or below 0)."""
    y = tame(peaks, *tail)
    if not log:
        return y
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(y > 0, np.log(y), np.nan)


def _usable(X: Array, y: Array) -> NDArray[np.bool_]:
    """The rows a GP is fitted on: finite control values and a finite fitted peak."""
    return np.isfinite(y) & np.isfinite(X).all(axis=1)


def fit_peak_model(
    target: str,
    decisions: Array,
    peaks: Array,
    max_length_scale: float = 1e5,
    log: bool = False,
    tail: tuple[float, float] = (0.0, 0.0),
) -> PeakModel:
    """A GP of ``peaks`` (their ``tail`` tamed; ``log``: of the logarithm of those) on
    ``decisions`` (rows with a finite, and for ``log`` positive, peak), hyperparameters by
    maximum marginal likelihood from one deterministic start (length scales 1 on standardised
    inputs)."""
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.gaussian_process import GaussianProcessRegressor

    X = np.asarray(decisions, dtype=float)
    y = _fitted(peaks, log, tail)
    keep = _usable(X, y)
    if keep.sum() < 3:
        raise ValueError(f"{keep.sum()} rows supply the {target} peak: a GP needs at least 3")
    X, y = X[keep], y[keep]
    mean = X.mean(axis=0)
    scale = np.where(X.std(axis=0) > 0, X.std(axis=0), 1.0)
    y_mean = float(y.mean())
    y_scale = float(y.std()) if y.std() > 0 else 1.0
    gp = GaussianProcessRegressor(peak_kernel(X.shape[1], max_length_scale), alpha=JITTER)
    with warnings.catch_warnings():
        # a control value the peak does not depend on takes the length scale's upper bound:
        # that is the answer ARD gives (irrelevant), not a failed fit
        warnings.simplefilter("ignore", ConvergenceWarning)
        gp.fit((X - mean) / scale, (y - y_mean) / y_scale)
    fitted = gp.kernel_.get_params()
    like = PeakModel(
        target=target,
        input_mean=mean,
        input_scale=scale,
        length_scale=np.broadcast_to(fitted["k1__k2__length_scale"], mean.shape).astype(float),
        amplitude=float(fitted["k1__k1__constant_value"]),
        noise=float(fitted["k2__noise_level"]),
        y_mean=y_mean,
        y_scale=y_scale,
        train_inputs=np.empty((0, mean.size)),
        weights=np.empty(0),
        log=log,
        tail=(float(tail[0]), float(tail[1])),
    )
    return like._on((X - mean) / scale, np.asarray(gp.alpha_, dtype=float))
