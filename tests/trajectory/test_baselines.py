"""Common trajectories: ends, derivatives, the ε warp and obstacle clearance."""

import numpy as np
import pytest

from ftfof import config
from ftfof.trajectory.baselines import Cycloidal, EpsBezier, Polynomial, eps_warp, obstacle_apex

P0, P15, T = np.zeros(2), np.array([0.12, 0.0]), 1.0
EPS = config.EpsBezier(epsilon=2.0, obstacle_x=(0.03, 0.09), obstacle_height=0.015)


def _all():
    return {
        "polynomial": Polynomial(P15 - P0, 0.035, T),
        "cycloidal": Cycloidal(P15 - P0, 0.035, T),
        "eps_bezier": EpsBezier.clearing(P0, P15, EPS, T),
    }


@pytest.mark.parametrize("name", ["polynomial", "cycloidal", "eps_bezier"])
def test_baselines_run_from_p0_to_p15_in_the_same_time(name):
    s = _all()[name].sample(np.array([0.0, T]))
    np.testing.assert_allclose(s.position[0, 0], P0, atol=1e-12)
    np.testing.assert_allclose(s.position[0, 1], P15, atol=1e-12)


@pytest.mark.parametrize("name", ["polynomial", "cycloidal", "eps_bezier"])
def test_baseline_derivatives_match_finite_differences(name):
    t = np.linspace(0, T, 20001)
    s = _all()[name].sample(t)
    v = np.gradient(s.position[0], t, axis=0)
    a = np.gradient(s.velocity[0], t, axis=0)
    np.testing.assert_allclose(s.velocity[0][3:-3], v[3:-3], atol=1e-6)
    np.testing.assert_allclose(s.acceleration[0][3:-3], a[3:-3], atol=1e-4)


def test_polynomial_and_cycloid_reach_the_lift_height():
    t = np.linspace(0, T, 2001)
    for traj in (_all()["polynomial"], _all()["cycloidal"]):
        assert traj.sample(t).position[0, :, 1].max() == pytest.approx(0.035)


def test_polynomial_starts_and_ends_at_rest():
    s = _all()["polynomial"].sample(np.array([0.0, T]))
    np.testing.assert_allclose(s.velocity, 0, atol=1e-12)
    np.testing.assert_allclose(s.acceleration, 0, atol=1e-12)


def test_eps_warp_maps_the_ends_and_is_point_symmetric():
    u = np.linspace(0, 1, 101)
    for eps in (0.5, 2.0, 4.0, 8.0):
        m, _, _ = eps_warp(u, eps)
        assert m[0] == pytest.approx(0.0, abs=1e-12) and m[-1] == pytest.approx(1.0)
        np.testing.assert_allclose(m + m[::-1], 1.0, atol=1e-12)


def test_eps_warp_tends_to_the_identity():
    u = np.linspace(0, 1, 101)
    gaps = [np.abs(eps_warp(u, eps)[0] - u).max() for eps in (2.0, 0.5, 0.1, 0.01)]
    assert gaps == sorted(gaps, reverse=True)
    assert gaps[-1] < 1e-4


def test_eps_warp_derivatives():
    u = np.linspace(0, 1, 10001)
    m, dm, ddm = eps_warp(u, 3.0)
    np.testing.assert_allclose(dm[2:-2], np.gradient(m, u)[2:-2], atol=1e-6)
    np.testing.assert_allclose(ddm[2:-2], np.gradient(dm, u)[2:-2], atol=1e-4)


def test_larger_eps_lands_slower_but_swings_faster():
    """ε-Bezier paper §III.B: end speed falls as eps grows; above eps ~ 1 the peak speed rises."""
    speeds = []
    for eps in (2.0, 4.0, 8.0):
        traj = EpsBezier.clearing(P0, P15, EPS.model_copy(update={"epsilon": eps}), T)
        v = np.linalg.norm(traj.sample(np.linspace(0, T, 2001)).velocity[0], axis=-1)
        speeds.append((v[-1], v.max()))
    end, peak = zip(*speeds, strict=True)
    assert end[-1] < 0.01 * end[0]
    assert list(end) == sorted(end, reverse=True)
    assert list(peak) == sorted(peak)


def test_eps_bezier_clears_the_obstacle_corners():
    traj = EpsBezier.clearing(P0, P15, EPS, T)
    pos = traj.sample(np.linspace(0, T, 20001)).position[0]
    for ox in EPS.obstacle_x:
        z_at = np.interp(ox, pos[:, 0], pos[:, 1])
        assert z_at > EPS.obstacle_height


def test_obstacle_apex_lies_on_both_sight_lines():
    o1, o2 = np.array([0.03, 0.015]), np.array([0.09, 0.015])
    op = obstacle_apex(P0, P15, o1, o2)

    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    assert cross(o1 - P0, op - P0) == pytest.approx(0.0, abs=1e-15)
    assert cross(o2 - P15, op - P15) == pytest.approx(0.0, abs=1e-15)
