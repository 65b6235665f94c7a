"""The peak GPs: what scikit-learn fits, NumPy predicts; ARD finds the control values that matter;
a refit on grown data learns the new rows at once."""

from __future__ import annotations

import json

import numpy as np
import pytest
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

from ftfof.data import tails
from ftfof.surrogate.peaks import (
    LOCAL_MAX_LENGTH_SCALE,
    LOG_PEAKS,
    NearFront,
    PeakModel,
    fit_peak_model,
    near_front,
    peak_model_from_dict,
)


def _peak(X: np.ndarray) -> np.ndarray:
    """A landing-press-like peak: smooth in two of five control values, blind to the rest."""
    return 5.0 + 0.8 * np.sin(3.0 * X[:, 0]) + 0.5 * X[:, 3] ** 2


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(3)
    X = rng.uniform(-1.0, 1.0, size=(160, 5))
    y = _peak(X) + rng.normal(0.0, 0.01, size=len(X))
    return X, y


@pytest.fixture(scope="module")
def model(data) -> PeakModel:
    X, y = data
    return fit_peak_model("Fp", X[:120], y[:120])


def test_it_predicts_held_out_peaks(model, data):
    X, _ = data
    error = np.abs(model(X[120:]) - _peak(X[120:]))
    assert np.median(error) < 0.03 and error.max() < 0.2


def test_ard_marks_the_control_values_the_peak_ignores(model):
    used, ignored = model.length_scale[[0, 3]], model.length_scale[[1, 2, 4]]
    assert ignored.min() > 10 * used.max()


@pytest.mark.filterwarnings("ignore::sklearn.exceptions.ConvergenceWarning")
def test_numpy_prediction_is_scikit_learns(model, data):
    """An independent scikit-learn fit, kernel written out here: same hyperparameters (a swapped
    parameter name in the export would show) and the same predictions."""
    X, y = data
    signal = ConstantKernel(1.0, (1e-3, 1e3)) * RBF(np.ones(5), (1e-2, 1e5))
    gp = GaussianProcessRegressor(signal + WhiteKernel(1e-2, (1e-6, 1.0)), normalize_y=True)
    scaled = (X - X[:120].mean(0)) / X[:120].std(0)
    gp.fit(scaled[:120], y[:120])
    fitted = gp.kernel_.get_params()
    np.testing.assert_allclose(model.length_scale, fitted["k1__k2__length_scale"], rtol=1e-3)
    np.testing.assert_allclose(model.amplitude, fitted["k1__k1__constant_value"], rtol=1e-3)
    np.testing.assert_allclose(model.noise, fitted["k2__noise_level"], rtol=1e-3)
    np.testing.assert_allclose(model(X), gp.predict(scaled), atol=1e-4)


def test_refit_on_the_same_rows_is_the_same_model(model, data):
    X, y = data
    np.testing.assert_allclose(model.refit(X[:120], y[:120])(X), model(X), atol=1e-9)


def test_refit_learns_rows_the_fit_never_saw():
    rng = np.random.default_rng(5)
    X = rng.uniform(-1.0, 1.0, size=(80, 2))
    first = fit_peak_model("jitter", X, X[:, 0] ** 2)
    far = np.array([[3.0, 0.0], [3.1, 0.1], [2.9, -0.1]])  # outside the box it was fitted in
    before = np.abs(first(far) - far[:, 0] ** 2).max()
    grown = first.refit(np.vstack([X, far]), np.concatenate([X[:, 0] ** 2, far[:, 0] ** 2]))
    after = np.abs(grown(far) - far[:, 0] ** 2).max()
    assert after < 0.1 * before


def test_saved_model_predicts_the_same(model, data):
    X, _ = data
    again = PeakModel.from_dict(json.loads(json.dumps(model.as_dict())))
    np.testing.assert_array_equal(again(X), model(X))
    assert again.target == "Fp" and again.train_inputs.shape == (120, 5)


def test_a_peak_is_never_negative():
    X = np.linspace(-1.0, 1.0, 30)[:, None]
    model = fit_peak_model("Fp", X, np.maximum(X[:, 0], 0.0) * 4.0)
    assert (model(np.linspace(-3.0, 3.0, 50)[:, None]) >= 0.0).all()


def test_wrong_inputs_are_named(model):
    with pytest.raises(ValueError, match="takes 5 control values, got 3"):
        model(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="2 rows supply the Fp peak"):
        fit_peak_model("Fp", np.zeros((4, 5)), np.array([1.0, 2.0, np.nan, np.nan]))


def _rippled(X: np.ndarray) -> np.ndarray:
    """Smooth over the box, with a fine ripple only near the origin (where a front would lie)."""
    near = np.exp(-(X**2).sum(axis=1) / 0.02)
    return 5.0 + X[:, 0] + 0.3 * np.sin(40.0 * X[:, 0]) * near


@pytest.fixture(scope="module")
def near():
    rng = np.random.default_rng(11)
    spread = rng.uniform(-1.0, 1.0, size=(150, 2))
    broad = fit_peak_model("Fp", spread, _rippled(spread))
    local = rng.uniform(-0.1, 0.1, size=(60, 2))
    return broad, local, near_front("Fp", broad, local, _rippled(local))


def test_near_front_learns_what_the_broad_gp_smooths_away(near):
    broad, _, model = near
    held_out = np.random.default_rng(12).uniform(-0.1, 0.1, size=(40, 2))
    truth = _rippled(held_out)
    broad_error = np.abs(broad(held_out) - truth).mean()
    assert broad_error > 0.05  # the ripple is there to be missed
    assert np.abs(model(held_out) - truth).mean() < 0.3 * broad_error


def test_near_front_is_the_broad_gp_far_from_the_rounds_points(near):
    broad, local, model = near
    far = np.array([[0.9, 0.9], [-0.8, 0.7], [0.7, -0.9]])
    assert model.confidence(far).max() < 1e-3
    np.testing.assert_allclose(model(far), broad(far), atol=1e-3)
    assert model.confidence(local).min() > 0.9
    assert model.target == "Fp" and model.length_scale is broad.length_scale


def test_saved_near_front_model_predicts_the_same(near, model):
    _, local, fitted = near
    again = peak_model_from_dict(json.loads(json.dumps(fitted.as_dict())))
    assert isinstance(again, NearFront)
    np.testing.assert_array_equal(again(local), fitted(local))
    assert isinstance(peak_model_from_dict(model.as_dict()), PeakModel)


def test_near_front_is_not_confident_far_along_a_value_the_rounds_peaks_ignore():
    """The rounds' peaks depend on x0 only: far along x2, 20 of the rounds' deviations off, the
    local GP must not claim to know (an unbounded length scale would make it blind to x2)."""
    rng = np.random.default_rng(13)
    spread = rng.uniform(-1.0, 1.0, size=(120, 3))
    broad = fit_peak_model("Fp", spread, 5.0 + spread[:, 0])
    local = rng.uniform(-0.1, 0.1, size=(50, 3))
    model = near_front("Fp", broad, local, 5.0 + local[:, 0] + 0.05 * np.sin(60.0 * local[:, 0]))
    assert model.local.length_scale[2] <= LOCAL_MAX_LENGTH_SCALE
    off = np.array([[0.0, 0.0, 20.0 * local[:, 2].std()]])
    assert model.confidence(local).min() > 0.9 and model.confidence(off)[0] < 0.1


def test_near_front_without_a_broad_gp_blends_with_the_series_maximum():
    """fsj's body acceleration has no broad GP: far from the rounds' points the series model's
    maximum stands, on them the local GP; the model refuses to guess without that maximum."""
    rng = np.random.default_rng(14)
    local = rng.uniform(-0.1, 0.1, size=(60, 2))
    model = near_front("body_acc", None, local, _rippled(local))
    far = np.array([[0.9, 0.9], [-0.8, 0.7]])
    series_peak = np.array([3.0, 4.0])
    np.testing.assert_allclose(model(far, series_peak), series_peak, atol=1e-3)
    held_out = rng.uniform(-0.08, 0.08, size=(20, 2))
    gru = np.full(len(held_out), 9.0)  # far off the truth
    assert np.abs(model(held_out, gru) - _rippled(held_out)).mean() < 0.1
    assert model.target == "body_acc" and model.length_scale is model.local.length_scale
    again = peak_model_from_dict(json.loads(json.dumps(model.as_dict())))
    assert again.broad is None
    np.testing.assert_array_equal(again(held_out, gru), model(held_out, gru))
    with pytest.raises(ValueError, match="blends with the series model's maximum"):
        model(held_out)


def test_a_log_local_gp_cannot_be_searched_below_its_smallest_peak():
    """The body's peak acceleration spans an order of magnitude near the front, with a steep
    rise beside its lowest values: a linear GP dipped below zero there and the optimiser went to
    the dips. A local GP of a LOG_PEAKS target is fitted on log(peak) and floored at the
    smallest peak it saw, so no search gets below that."""
    rng = np.random.default_rng(15)
    X = rng.uniform(-1.0, 1.0, size=(60, 3))
    peaks = 0.5 + 10.0 / (1.0 + np.exp(-12.0 * X[:, 0]))  # 0.5 .. 10.5, a cliff at x0 = 0
    assert "body_acc" in LOG_PEAKS
    model = near_front("body_acc", None, X, peaks)
    assert model.local.log and model.local.floor == pytest.approx(peaks.min())
    probes = rng.uniform(-1.0, 1.0, size=(20000, 3))
    assert model(probes, np.full(len(probes), 5.0)).min() >= peaks.min()
    linear = fit_peak_model("body_acc", X, peaks, LOCAL_MAX_LENGTH_SCALE)
    assert not linear.log and linear.floor == 0.0  # a broad GP keeps its zero floor
    assert linear(probes).min() < peaks.min()  # the dip the floor and the log close
    again = peak_model_from_dict(json.loads(json.dumps(model.as_dict())))
    np.testing.assert_array_equal(again.local(probes[:50]), model.local(probes[:50]))
    assert again.local.log and again.local.floor == model.local.floor


def test_a_saved_model_from_before_log_peaks_loads_as_linear(model):
    old = {k: v for k, v in model.as_dict().items() if k not in ("log", "floor", "tail")}
    again = peak_model_from_dict(old)
    assert not again.log and again.floor == 0.0
    X = np.random.default_rng(16).uniform(-2.0, 2.0, size=(7, len(model.input_mean)))
    np.testing.assert_array_equal(again(X), model(X))


def test_a_log_model_refits_on_its_positive_peaks_only():
    rng = np.random.default_rng(17)
    X = rng.uniform(-1.0, 1.0, size=(40, 2))
    peaks = np.exp(X[:, 0])
    model = fit_peak_model("body_acc", X, peaks, LOCAL_MAX_LENGTH_SCALE, log=True)
    again = model.refit(np.vstack([X, [[0.5, 0.5]]]), np.append(peaks, 0.0))  # a zero: no log
    assert again.train_inputs.shape == (40, 2)
    np.testing.assert_allclose(again(X), model(X))


def test_a_tamed_gp_is_not_ruled_by_a_few_huge_peaks():
    """The landing press: 5 N give or take 0.3 N, and two hard landings of 50-150 N. Fitted as
    they are, the outliers set the GP's scale and it misses the bulk; tamed, it learns it."""
    rng = np.random.default_rng(21)
    X = rng.uniform(-1.0, 1.0, size=(150, 3))
    peaks = 5.0 + 0.3 * np.sin(2.0 * X[:, 0])
    hard = rng.choice(120, 2, replace=False)
    peaks[hard] = rng.uniform(50.0, 150.0, 2)
    bulk = np.arange(120, 150)
    tail = tails.fence(peaks[:120], 3.0)
    raw = fit_peak_model("Fp", X[:120], peaks[:120])
    tamed = fit_peak_model("Fp", X[:120], peaks[:120], tail=tail)
    error = np.median(np.abs(tamed(X[bulk]) - peaks[bulk]))
    assert error < 0.1 and error < 0.2 * np.median(np.abs(raw(X[bulk]) - peaks[bulk]))
    assert tamed(X[hard]).min() > tail[0]  # a hard landing still reads as one, past the fence
    again = peak_model_from_dict(json.loads(json.dumps(tamed.as_dict())))
    assert again.tail == tamed.tail
    np.testing.assert_array_equal(again(X[bulk]), tamed(X[bulk]))
    np.testing.assert_allclose(tamed.refit(X[:120], peaks[:120])(X[bulk]), tamed(X[bulk]))
