"""Tamed tails: the identity up to the fence, monotone above it, exactly invertible."""

from __future__ import annotations

import numpy as np

from ftfof.data import dataset, tails


def test_the_fence_is_tukeys_far_out_fence_and_zero_spread_turns_it_off():
    peaks = np.array([1.0, 2.0, 3.0, 4.0, 5.0, np.nan, 100.0])
    upper, spread = tails.fence(peaks, 3.0)
    q1, q3 = np.percentile(peaks[np.isfinite(peaks)], [25, 75])
    assert (upper, spread) == (q3 + 3.0 * (q3 - q1), q3 - q1)
    assert tails.fence(peaks, 0.0) == (0.0, 0.0)
    assert tails.fence(np.zeros(9), 3.0) == (0.0, 0.0)  # a target that never varies: as it is
    assert tails.fence(np.full(4, np.nan), 3.0) == (0.0, 0.0)


def test_taming_keeps_the_bulk_and_the_order_and_inverts():
    y = np.array([np.nan, 0.0, 7.0, 13.9, 14.0, 20.0, 80.0, 156.0])
    g = tails.tame(y, 14.0, 1.6)
    np.testing.assert_array_equal(g[1:5], y[1:5])  # up to the fence: unchanged
    assert np.isnan(g[0]) and np.all(np.diff(g[1:]) > 0)  # monotone: an outlier stays largest
    assert g[-1] < 14.0 + 1.6 * np.log(156.0)  # 80 N and 156 N are now a few IQRs out
    np.testing.assert_allclose(tails.untame(g, 14.0, 1.6), y, rtol=1e-12)
    np.testing.assert_array_equal(tails.tame(y, 14.0, 0.0), y)


def test_normalisation_tames_each_target_by_its_training_peaks():
    rng = np.random.default_rng(5)
    targets = rng.uniform(0.0, 1.0, size=(40, 16, 3))
    targets[0, 3, 0] = 50.0  # one pad that did not let go
    targets[..., 2] = 0.0  # a target that never varies
    inputs = rng.normal(size=(40, 16, 4))
    norm = dataset.Normalization.fit(inputs, targets, tail_fence=3.0)
    assert norm.tail(0)[1] > 0 and norm.tail(0)[0] < 50.0 and norm.tail(2) == (0.0, 0.0)
    model = norm.to_model(targets)
    assert model[0, 3, 0] * norm.target_scale[0] < 10.0  # the outlier no longer rules the MSE
    np.testing.assert_allclose(norm.from_model(model), targets, rtol=1e-9, atol=1e-12)
    assert dataset.Normalization.from_json(norm.to_json()) == norm
    off = dataset.Normalization.fit(inputs, targets, tail_fence=0.0)
    np.testing.assert_allclose(off.to_model(targets), targets / np.asarray(off.target_scale))


def test_a_normalisation_saved_before_tails_loads_untamed():
    old = '{"input_mean": [0.0], "input_scale": [1.0], "target_scale": [2.0, 4.0]}'
    norm = dataset.Normalization.from_json(old)
    y = np.array([[1.0, 100.0]])
    np.testing.assert_array_equal(norm.to_model(y), y / [2.0, 4.0])
    np.testing.assert_array_equal(norm.from_model(norm.to_model(y)), y)


def test_a_prediction_far_past_the_fence_maps_back_finite_and_in_order():
    from ftfof.data.tails import MAX_EXCESS, untame

    g = np.array([2.0, 2.0 + MAX_EXCESS, 2.0 + 1e3, 2.0 + 1e6, np.nan])
    out = untame(g, upper=2.0, spread=0.5)
    assert np.isfinite(out[:4]).all() and np.isnan(out[4])
    assert np.all(np.diff(out[:2]) > 0) and out[2] == out[1] == out[3]
