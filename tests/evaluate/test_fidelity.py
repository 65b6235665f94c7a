"""Surrogate fidelity: error and rank statistics, simulated objectives on the training bins."""

import numpy as np
import pytest

from ftfof.data.targets import time_base
from ftfof.evaluate.fidelity import fidelity, relative_error, simulated_objectives, target_met
from ftfof.trajectory.sampling import sample_feasible


def test_perfect_and_reversed_predictions():
    s = np.array([[1.0, 5.0], [2.0, 4.0], [3.0, 3.0], [4.0, 2.0]])
    exact = fidelity(["a", "b"], s, s)
    assert [f.mean_abs_error for f in exact] == [0.0, 0.0]
    assert [f.spearman for f in exact] == [pytest.approx(1.0), pytest.approx(1.0)]
    reversed_ = fidelity(["a", "b"], s[::-1], s)
    assert reversed_[0].spearman == pytest.approx(-1.0)
    half = fidelity(["a", "b"], 1.5 * s, s)[0]
    assert half.median_relative_error == pytest.approx(0.5)


def test_constant_column_has_no_rank_correlation_and_shapes_are_checked():
    s = np.ones((4, 1))
    assert np.isnan(fidelity(["a"], s, s)[0].spearman)
    with pytest.raises(ValueError, match="must both be"):
        fidelity(["a", "b"], s, s)


def test_the_target_needs_rank_median_and_optimum_alike():
    s = np.arange(1.0, 6.0)[:, None]
    good = fidelity(["fs1"], 1.1 * s, s)[0]  # rho 1, every point 10 % off
    assert relative_error(1.1, 1.0) == pytest.approx(0.1) and np.isnan(relative_error(1.0, 0.0))
    assert target_met(good, 0.1, 0.9, 0.15)
    assert not target_met(good, 0.2, 0.9, 0.15)  # the optimum itself too far off
    assert not target_met(good, 0.1, 0.9, 0.05)  # the median too far off
    assert not target_met(fidelity(["fs1"], s[::-1], s)[0], 0.0, 0.9, 10.0)  # ranks reversed
    assert not target_met(fidelity(["fs1"], np.ones((5, 1)), s)[0], 0.0, -1.0, 10.0)  # NaN rho


def test_simulated_objectives_bin_the_channels_like_the_dataset(m3f):
    policy = m3f.policy
    X = sample_feasible(policy, 2, seed=1).X
    T3, hold = policy.timing.T3, 0.25
    t = np.arange(-0.2, T3 + 0.3, 1e-3)  # the platform records before and after the step
    records = []
    for p in (0.3 * T3, 0.6 * T3):
        fz = 4.0 * np.exp(-(((t - p) / 0.02) ** 2)) - 5.2 * np.exp(-(((t - T3) / 0.05) ** 2))
        records.append(
            {
                "t": t,
                "Fx_pad": 3.0 * np.exp(-(((t - p) / 0.02) ** 2)),
                "Fz_pad": fz,
                "bonds": np.where(t < p + 0.05, 10.0, 0.0),
                "switch": (t > p + 0.06).astype(float),
                "body_acc": 1.0 + 20.0 * np.exp(-(((t - p - 0.05) / 0.005) ** 2)),
            }
        )
    force_t = time_base(T3, hold, 64)
    F = simulated_objectives(
        ["fs1", "fs3", "fsj", "fs1_normal"], policy, X, records, force_t, hold, pre_pressure=5.0
    )
    np.testing.assert_allclose(F[:, 0], 5.0, rtol=1e-3)  # the resultant: bin maxima keep it
    np.testing.assert_allclose(F[:, 1], 0.2, atol=1e-3)  # the landing pre-pressure
    np.testing.assert_allclose(F[:, 2], 21.0, rtol=1e-3)  # the release ring
    np.testing.assert_allclose(F[:, 3], 4.0, rtol=1e-3)
