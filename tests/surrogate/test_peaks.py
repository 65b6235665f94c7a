"""The peak GPs: what scikit-learn fits, NumPy predicts; ARD finds the control values that matter;
a refit on grown data learns the new rows at once."""

from __future__ import annotations

import json

import numpy as np
import pytest
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

from ftfof.surrogate.peaks import PeakModel, fit_peak_model


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
