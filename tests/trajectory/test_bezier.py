"""The three-segment quintic Bezier: joins, ends, derivatives and the published optimum."""

import numpy as np
import pytest

from ftfof.config import Timing
from ftfof.trajectory.bezier import (
    control_points,
    control_points_from_free,
    decision_to_points,
    evaluate,
    evaluate_points,
    points_to_decision,
    same_trajectory,
)
from tests.conftest import PUBLISHED_M3F

THIRDS = Timing(T1=1 / 3, T2=2 / 3, T3=1.0)
UNEQUAL = Timing(T1=0.3, T2=0.7, T3=1.0)
P0, P15 = np.zeros(2), np.array([0.12, 0.0])


def test_published_optimum_swing_peaks_at_64_mm_with_equal_thirds():
    s = evaluate(PUBLISHED_M3F, P0, P15, THIRDS, THIRDS.grid(20001))
    assert s.position[0, :, 1].max() * 1000 == pytest.approx(64.0, abs=0.1)
    # ... although its swing control points P8, P9 lie above Pplz = 64 mm (FTFOF §VI.A).
    P = control_points(PUBLISHED_M3F, P0, P15, THIRDS)
    assert P[8, 1] * 1000 == pytest.approx(83.5, abs=0.05)
    assert P[9, 1] * 1000 == pytest.approx(66.7, abs=0.05)


def test_same_points_with_another_split_give_another_curve_near_70_mm():
    s = evaluate(PUBLISHED_M3F, P0, P15, UNEQUAL, UNEQUAL.grid(20001))
    assert 68.0 < s.position[0, :, 1].max() * 1000 < 72.0


def test_equal_durations_reduce_to_paper_eq5():
    P = control_points(PUBLISHED_M3F, P0, P15, THIRDS)
    np.testing.assert_allclose(P[6], 2 * P[5] - P[4])
    np.testing.assert_allclose(P[9], 2 * P[10] - P[11])
    np.testing.assert_allclose(P[7], 4 * (P[5] - P[4]) + P[3])
    np.testing.assert_allclose(P[8], 4 * (P[10] - P[11]) + P[12])


def _one_sided(timing: Timing, X: np.ndarray, t_join: float, h: float):
    """Finite-difference velocity and acceleration from the left and from the right of a join."""
    left = t_join - h * np.arange(3)[::-1]
    right = t_join + h * np.arange(3)
    pl = evaluate(X, P0, P15, timing, left).position[0]
    pr = evaluate(X, P0, P15, timing, right).position[0]
    vl, vr = (pl[2] - pl[1]) / h, (pr[1] - pr[0]) / h
    al, ar = (pl[2] - 2 * pl[1] + pl[0]) / h**2, (pr[2] - 2 * pr[1] + pr[0]) / h**2
    return (vl, al), (vr, ar)


@pytest.mark.parametrize("t_join", [UNEQUAL.T1, UNEQUAL.T2])
def test_physical_velocity_and_acceleration_are_continuous_at_unequal_joins(t_join):
    h = 1e-5
    (vl, al), (vr, ar) = _one_sided(UNEQUAL, PUBLISHED_M3F, t_join, h)
    scale_v = np.abs(vl).max()
    np.testing.assert_allclose(vl, vr, atol=1e-3 * scale_v)
    np.testing.assert_allclose(al, ar, atol=2e-2 * np.abs(al).max())


def test_naive_eq5_with_unequal_durations_would_break_velocity():
    """The check above can fail: eq. 5 applied to unequal segments jumps the velocity."""
    P = control_points(PUBLISHED_M3F, P0, P15, UNEQUAL)
    P[6] = 2 * P[5] - P[4]  # equal-duration rule
    t = np.array([UNEQUAL.T1 - 1e-9, UNEQUAL.T1 + 1e-9])
    v = evaluate_points(P[None], UNEQUAL, t).velocity[0]
    assert np.abs(v[0] - v[1]).max() > 0.01


def test_zero_velocity_and_acceleration_at_both_ends():
    s = evaluate(PUBLISHED_M3F, P0, P15, UNEQUAL, np.array([0.0, UNEQUAL.T3]))
    np.testing.assert_allclose(s.position[0, 0], P0, atol=1e-15)
    np.testing.assert_allclose(s.position[0, 1], P15, atol=1e-15)
    np.testing.assert_allclose(s.velocity[0], 0.0, atol=1e-12)
    np.testing.assert_allclose(s.acceleration[0], 0.0, atol=1e-10)


def test_analytic_derivatives_match_finite_differences():
    t = UNEQUAL.grid(40001)
    s = evaluate(PUBLISHED_M3F, P0, P15, UNEQUAL, t)
    v_fd = np.gradient(s.position[0], t, axis=0)
    a_fd = np.gradient(s.velocity[0], t, axis=0)
    np.testing.assert_allclose(s.velocity[0][2:-2], v_fd[2:-2], atol=1e-5)
    np.testing.assert_allclose(s.acceleration[0][2:-2], a_fd[2:-2], atol=2e-3)


def test_population_evaluation_equals_one_at_a_time():
    rng = np.random.default_rng(0)
    X = PUBLISHED_M3F + rng.normal(scale=0.003, size=(7, 12))
    t = THIRDS.grid(64)
    whole = evaluate(X, P0, P15, THIRDS, t)
    assert whole.position.shape == (7, 64, 2)
    for i in range(7):
        one = evaluate(X[i], P0, P15, THIRDS, t)
        np.testing.assert_allclose(whole.position[i], one.position[0], rtol=0, atol=1e-15)
        np.testing.assert_allclose(
            whole.acceleration[i], one.acceleration[0], rtol=1e-12, atol=1e-12
        )


def test_control_points_are_dimension_agnostic():
    """A lateral y component rides along with no change to the maths."""
    free2 = decision_to_points(PUBLISHED_M3F)
    free3 = np.concatenate([free2, np.linspace(0, 0.01, 6)[:, None]], axis=-1)
    P3 = control_points_from_free(free3[None], np.zeros(3), np.r_[P15, 0.0], UNEQUAL)
    P2 = control_points_from_free(free2[None], P0, P15, UNEQUAL)
    np.testing.assert_allclose(P3[..., :2], P2)
    s = evaluate_points(P3, UNEQUAL, UNEQUAL.grid(33))
    assert s.position.shape == (1, 33, 3)


def test_decision_vector_round_trip():
    np.testing.assert_array_equal(
        points_to_decision(decision_to_points(PUBLISHED_M3F)), PUBLISHED_M3F
    )


def test_same_trajectory_matches_decision_rows_to_a_nanometre():
    rows = np.array([np.full(12, 0.01), np.full(12, 0.02)])
    X = np.vstack([rows[1] + 5e-10, rows[0] + 2e-9, np.full(12, 0.03)])
    assert same_trajectory(X, rows).tolist() == [True, False, False]
    assert same_trajectory(X, None).tolist() == [False] * 3
    assert same_trajectory(X[:0], rows).shape == (0,)
