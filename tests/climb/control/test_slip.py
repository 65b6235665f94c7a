"""Slip detection, the slip rate, the weight adaptation and the pad estimate at a slipping foot."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ftfof.climb.control.forces import ForceDistributor
from ftfof.climb.control.slip import (
    SlipDetector,
    adapt_weights,
    cone_of,
    estimate_adhesion,
    fit_pad,
    slip_rate,
)
from ftfof.identify.estimate import Estimate
from tests.climb.control.stances import stance_of, static_wrench

DT = 1e-3  # s, a control step
THRESHOLD, HOLD = 0.01, 0.005  # m/s, s


def test_a_slip_is_declared_only_after_the_hold_time():
    detector = SlipDetector(THRESHOLD, HOLD)
    stance = np.array([True, True, True, False])
    fast = np.array([0.0, -0.02, 0.02, 0.5])  # FR slides down, HL up, HR swings
    seen = [detector.update(fast, stance, DT).copy() for _ in range(6)]
    assert not np.any(seen[:4])
    assert seen[4].tolist() == [False, True, True, False]  # 5 steps: the hold
    assert seen[5].tolist() == [False, True, True, False]


def test_a_slip_resets_when_the_foot_slows_or_lifts():
    detector = SlipDetector(THRESHOLD, HOLD)
    stance = np.ones(4, dtype=bool)
    fast = np.full(4, 0.02)
    for _ in range(5):
        detector.update(fast, stance, DT)
    assert detector.slipping.all()
    slowed = np.array([0.02, THRESHOLD, 0.02, 0.02])  # at the threshold is not above it
    lifted = np.array([True, True, True, False])
    assert detector.update(slowed, lifted, DT).tolist() == [True, False, True, False]
    for _ in range(4):
        assert not detector.update(fast, stance, DT)[1]  # the count starts again
    assert detector.update(fast, stance, DT).all()
    detector.reset()
    assert not detector.slipping.any()


def test_the_slip_rate_is_zero_to_the_threshold_then_rises_and_saturates():
    speed = np.linspace(0.0, 0.15, 151)
    rate = slip_rate(speed, THRESHOLD, span=0.02)
    assert not rate[speed <= THRESHOLD].any()
    above = rate[speed > THRESHOLD]
    assert np.all(np.diff(above) > 0) and above[-1] < 1.0 and above[-1] > 0.999
    assert slip_rate(np.array([THRESHOLD + 1e-9]), THRESHOLD, 0.02)[0] < 1e-6  # continuous
    assert slip_rate(-speed, THRESHOLD, 0.02) == pytest.approx(rate)  # either way along the wall


def test_the_adapted_weights_raise_the_tangential_and_lower_the_normal():
    nominal = np.tile([1.0, 1e-3], (4, 1))
    out = adapt_weights(nominal, np.array([0.0, 0.5, 1.0, 0.0]), max_factor=400.0)
    assert out[[0, 3]] == pytest.approx(nominal[[0, 3]])
    assert out[1] == pytest.approx([20.0, 1e-3 / 20.0])
    assert out[2] == pytest.approx([400.0, 1e-3 / 400.0])


@pytest.mark.parametrize("foot", [1, 2])  # a fore foot that pulls, a hind foot that presses
def test_the_adapted_qp_moves_a_slipping_foot_toward_its_normal(m3f, foot):
    stance = stance_of(m3f)
    rate = np.zeros(4)
    rate[foot] = 0.3
    adapted = replace(stance, weight=adapt_weights(stance.weight, rate))
    before = ForceDistributor().solve(stance, static_wrench())
    after = ForceDistributor().solve(adapted, static_wrench())
    assert after.solved and np.abs(after.residual).max() < 1e-4 * static_wrench()[0]

    def ratio(out):
        ft, fn = out.forces[foot]
        return abs(ft) / (fn + stance.adhesion[foot])

    assert ratio(after) < 0.5 * ratio(before)
    assert abs(after.forces[foot, 0]) < abs(before.forces[foot, 0])
    # its normal force is left free, and the others are pulled no harder than any foot was:
    # weighed from the pyramid's apex, they were pulled toward -F_adh (issue 40)
    others = np.delete(after.forces[:, 1], foot)
    assert others.min() >= before.forces[:, 1].min() - 1e-6


MU, ADHESION = 0.6, 8.0


def _slip_window(seed: int = 0, samples: int = 30) -> tuple[np.ndarray, np.ndarray]:
    """A slipping pad's forces under R = 0.25 N^2 noise: the normal load varied throughout the
    window, the pad sliding down (friction on the foot up the wall, f_t > 0). 30 samples are
    30 ms at the force sensor's and the controller's 1 kHz: two of the Kalman filter's windows."""
    rng = np.random.default_rng(seed)
    fn = rng.uniform(-3.0, 10.0, samples)
    ft = MU * (fn + ADHESION) + rng.normal(0.0, 0.5, samples)
    return fn, ft


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("method", ["kalman", "least_squares"])
def test_the_estimate_recovers_the_pad_within_ten_percent_in_30_ms(method, seed):
    fn, ft = _slip_window(seed)
    prior = Estimate(0.45, 5.6)  # the controller assumed a pad 25-30 % off
    for sign in (1.0, -1.0):  # sliding down or up: the friction law sees |f_t|
        est = cone_of(fit_pad(fn, sign * ft, method, prior))
        assert est.mu == pytest.approx(MU, rel=0.1)
        assert est.adhesion == pytest.approx(ADHESION, rel=0.1)


def test_the_estimate_refuses_an_unknown_method_or_a_kalman_without_prior():
    fn, ft = _slip_window()
    with pytest.raises(ValueError, match="prior"):
        fit_pad(fn, ft, "kalman")
    with pytest.raises(ValueError, match="unknown estimator"):
        fit_pad(fn, ft, "median")  # type: ignore[arg-type]


def _peel_window() -> tuple[np.ndarray, np.ndarray]:
    """FR's last 15 ms before it let go in issue 40's scenario, as a law: a pad losing its bonds
    as it slides, its shear capacity falling with its pull, so f_t and f_n fall together."""
    fn = np.linspace(-3.8, -0.5, 15)
    adhesion = np.linspace(10.0, 2.0, 15)  # what it still holds, N
    return fn, MU * (fn + adhesion)


def test_a_pad_that_loses_its_bonds_as_it_slides_fits_a_negative_mu():
    fn, ft = _peel_window()
    assert fit_pad(fn, ft, "least_squares").mu < 0


def test_the_adhesion_estimate_with_mu_known_is_what_the_peeling_pad_still_holds():
    fn, ft = _peel_window()
    assert estimate_adhesion(fn, -ft, MU) == pytest.approx(6.0, rel=1e-9)  # the window's mean
    fn, ft = _slip_window()
    assert estimate_adhesion(fn, ft, MU) == pytest.approx(ADHESION, rel=0.05)
    with pytest.raises(ValueError, match="positive mu"):
        estimate_adhesion(fn, ft, 0.0)
