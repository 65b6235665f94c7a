"""The estimators on synthetic slip data of known friction and adhesion, with sensor noise."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.identify.estimate import Estimate, kalman, least_squares
from ftfof.identify.log import SlipLog, slip_samples

MU, ADHESION = 0.45, 13.5  # F_adh in newtons of shear: F_t = mu F_n + F_adh


def _synthetic(noise: float, n: int = 600, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    fn = np.repeat(np.linspace(-5.0, 10.0, 6), n // 6)  # pulls and presses, in blocks
    ft = MU * fn + ADHESION + rng.normal(0.0, noise, fn.size)
    return fn, ft


def test_least_squares_recovers_noise_free_truth():
    fn, ft = _synthetic(0.0)
    est = least_squares(fn, ft)
    assert est.mu == pytest.approx(MU, rel=1e-9)
    assert est.adhesion == pytest.approx(ADHESION, rel=1e-9)


def test_kalman_converges_from_a_start_20_percent_off_under_noise():
    fn, ft = _synthetic(0.5)
    track = kalman(fn, ft, Estimate(0.55, 10.8))
    assert track.final.mu == pytest.approx(MU, rel=0.05)
    assert track.final.adhesion == pytest.approx(ADHESION, rel=0.05)
    assert track.samples[-1] == 600 and track.mu.size == 40  # one update per 15 samples


def test_kalman_is_linear_in_its_state_so_a_far_start_does_not_trap_it():
    """The old form mu (F_n + F_adh) left a filter started far off on the wrong branch of
    mu F_adh = const; the tangential form has no such branch."""
    fn, ft = _synthetic(0.5)
    far = kalman(fn, ft, Estimate(0.8, 2.0)).final
    assert far.mu == pytest.approx(MU, rel=0.05)
    assert far.adhesion == pytest.approx(ADHESION, rel=0.05)


def test_kalman_refuses_fewer_samples_than_a_window():
    fn, ft = _synthetic(0.0, n=12)
    with pytest.raises(ValueError, match="at least 15"):
        kalman(fn, ft, Estimate(0.5, 10.0))


def test_slip_samples_are_each_runs_top_band_up_to_its_peak():
    ft = np.array([0.0, 5.0, 9.92, 10.0, 2.0, 0.0, 19.85, 20.0, 19.9, 1.0])
    load = np.array([1.0] * 5 + [2.0] * 5)
    log = SlipLog(np.arange(10.0), ft, -load, load)
    assert np.flatnonzero(slip_samples(log)).tolist() == [2, 3, 6, 7]
