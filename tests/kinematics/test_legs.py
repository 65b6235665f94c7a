"""Leg kinematics: forward/inverse round trips, Jacobians, and the ε-Bezier paper's eq. 6."""

import numpy as np
import pytest

from ftfof.kinematics.legs import build_leg, joint_excess, joint_rates, within_limits


@pytest.fixture(params=["mst_m3f", "mst_q"])
def leg(request, params):
    return build_leg(params.robots[request.param].leg)


def _random_angles(leg, n, rng):
    lo, hi = leg.joint_limits[:, 0], leg.joint_limits[:, 1]
    free = leg.sagittal_angles(
        lo[list(leg.free_joints)] + rng.random((n, 2)) * (hi - lo)[list(leg.free_joints)]
    )
    return free[np.all(np.isfinite(free), axis=1)]


def test_forward_of_inverse_returns_the_point_across_the_workspace(leg):
    rng = np.random.default_rng(0)
    theta = _random_angles(leg, 3000, rng)
    points = leg.forward(theta)  # points the leg can reach
    back = leg.forward(leg.inverse(points))
    np.testing.assert_allclose(back, points, atol=1e-12)


def test_inverse_of_forward_returns_the_angles_on_the_working_branch(leg):
    rng = np.random.default_rng(1)
    theta = _random_angles(leg, 3000, rng)
    recovered = leg.inverse(leg.forward(theta))
    same_branch = np.all(np.isfinite(recovered), axis=1) & within_limits(
        recovered, leg.joint_limits
    )
    assert same_branch.mean() > 0.5
    np.testing.assert_allclose(recovered[same_branch], theta[same_branch], atol=1e-9)


def test_unreachable_points_give_nan(leg):
    assert np.all(np.isnan(leg.inverse(np.array([5.0, 5.0]))))


def test_jacobian_matches_finite_differences(leg):
    rng = np.random.default_rng(2)
    theta = _random_angles(leg, 20, rng)
    J = leg.jacobian(theta)
    h = 1e-7
    for j in range(3):
        step = np.zeros(3)
        step[j] = h
        fd = (leg.forward(theta + step) - leg.forward(theta - step)) / (2 * h)
        np.testing.assert_allclose(J[:, :, j], fd, atol=1e-7)


def test_sagittal_rates_keep_the_foot_in_the_plane(params):
    leg = build_leg(params.robots["mst_q"].leg)
    rng = np.random.default_rng(3)
    theta = _random_angles(leg, 50, rng)
    rates = leg.sagittal_rates(theta, rng.normal(size=(len(theta), 2)))
    ydot = np.einsum("pj,pj->p", leg.jacobian3(theta)[:, 1, :], rates)
    np.testing.assert_allclose(ydot, 0.0, atol=1e-12)


def test_planar_inverse_keeps_the_plate_parallel(params):
    leg = build_leg(params.robots["mst_m3f"].leg)
    theta = leg.inverse(np.array([[0.0, 0.0], [0.12, 0.0], [0.16, 0.064]]))
    np.testing.assert_allclose(theta.sum(axis=1), 0.0, atol=1e-12)


def test_spatial_inverse_agrees_with_eps_bezier_eq6_as_printed(params):
    """eq. 6: theta3 = acos((k^2 + Px^2 - d2^2 - d3^2) / (2 d2 d3)),
    theta2 = -acos((k^2 + Px^2 + d2^2 - d3^2) / (2 d2 sqrt(k^2 + Px^2))) + eta,
    eta = atan(Px / k)."""
    leg = build_leg(params.robots["mst_q"].leg)
    rng = np.random.default_rng(4)
    theta = _random_angles(leg, 200, rng)
    p3 = leg.forward3(theta)
    px = p3[:, 0] - leg.hip[0]
    k = np.hypot(p3[:, 1] - leg.y0, leg.hip[1] - p3[:, 2]) - leg.d1 - leg.d4
    r2 = k**2 + px**2
    t3 = np.arccos((r2 - leg.d2**2 - leg.d3**2) / (2 * leg.d2 * leg.d3))
    t2 = -np.arccos((r2 + leg.d2**2 - leg.d3**2) / (2 * leg.d2 * np.sqrt(r2))) + np.arctan2(px, k)
    ours = leg.inverse3(p3)
    np.testing.assert_allclose(ours[:, 2], t3, atol=1e-9)
    np.testing.assert_allclose(ours[:, 1], t2, atol=1e-9)


def _path_through(leg, theta, rates):
    """Foot positions and velocities (1, n, 2) of the joint motion ``theta``, ``rates`` (n, 3)."""
    points = leg.forward(theta)
    velocity = np.einsum("nij,nj->ni", leg.jacobian(theta), rates)
    return points[None], velocity[None]


def test_joint_rates_invert_the_jacobian_on_the_sagittal_motion(leg):
    rng = np.random.default_rng(1)
    theta = _random_angles(leg, 500, rng)
    rates = leg.sagittal_rates(theta, rng.normal(size=(len(theta), 2)))
    velocity = np.einsum("nij,nj->ni", leg.jacobian(theta), rates)
    np.testing.assert_allclose(joint_rates(leg, theta, velocity), rates, atol=1e-9)


def test_joint_excess_is_the_worst_joint_speed_over_its_limit_and_one_where_unreachable(leg):
    rng = np.random.default_rng(2)
    inside = _random_angles(leg, 4000, rng)
    same_branch = np.all(np.abs(leg.inverse(leg.forward(inside)) - inside) < 1e-9, axis=1)
    inside = inside[same_branch & within_limits(inside, leg.joint_limits, tol=-0.05)][:20]
    free = np.zeros((len(inside), 2))
    free[:, 0] = 0.5 * leg.speed_limits[leg.free_joints[0]]
    rates = leg.sagittal_rates(inside, free)
    slow = rates / max(1.0, float(np.max(np.abs(rates) / leg.speed_limits)) / 0.5)
    assert joint_excess(leg, *_path_through(leg, inside, slow))[0] < 0  # within every limit
    ratio = float(np.max(np.abs(slow) / leg.speed_limits))
    fast = slow * (1.2 / ratio)  # the fastest joint 20 % past its limit
    assert joint_excess(leg, *_path_through(leg, inside, fast))[0] == pytest.approx(0.2, rel=1e-6)
    far = np.full((1, 3, 2), 10.0)  # out of reach
    assert joint_excess(leg, far, np.zeros_like(far))[0] == 1.0
