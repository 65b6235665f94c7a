"""Ppl and Vpl from the leg (FTFOF eq. 7-8): NSGA-II against brute force, pinning, safety."""

import copy

import numpy as np
import pytest

from ftfof.config import Params
from ftfof.errors import InfeasibleRobotError
from ftfof.kinematics.legs import build_leg, within_limits
from ftfof.kinematics.limits import position_reach, resolve_limits, velocity_reach


@pytest.fixture(scope="module", params=["mst_m3f", "mst_q"])
def leg(request, params):
    return build_leg(params.robots[request.param].leg)


def _grid_angles(leg, n):
    free = list(leg.free_joints)
    lo, hi = leg.joint_limits[free, 0], leg.joint_limits[free, 1]
    a, b = np.meshgrid(np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n))
    theta = leg.sagittal_angles(np.stack([a.ravel(), b.ravel()], axis=-1))
    ok = np.all(np.isfinite(theta), axis=1) & within_limits(theta, leg.joint_limits)
    return theta[ok]


def test_position_reach_matches_a_dense_grid_search(leg):
    result = position_reach(leg, 0.85, seed=0)
    theta = _grid_angles(leg, 600)
    p = leg.forward(theta)
    ok = (p[:, 1] <= p[:, 0]) & np.all(p > 0, axis=1)
    best = np.max(p[ok, 0] * p[ok, 1])
    found = result.raw[0] * result.raw[1]
    assert found == pytest.approx(best, rel=0.02)
    # the extreme is reachable and satisfies eq. 7's z <= x
    np.testing.assert_allclose(leg.forward(result.theta), result.raw, atol=1e-9)
    assert result.raw[1] <= result.raw[0] + 1e-9
    np.testing.assert_allclose(result.value, 0.85 * result.raw)


def test_velocity_reach_beats_random_search(leg):
    result = velocity_reach(leg, 0.8, seed=0)
    rng = np.random.default_rng(0)
    free = list(leg.free_joints)
    lim, spd = leg.joint_limits[free], leg.speed_limits[free]
    n = 200_000
    theta = leg.sagittal_angles(lim[:, 0] + rng.random((n, 2)) * (lim[:, 1] - lim[:, 0]))
    rates = leg.sagittal_rates(theta, (2 * rng.random((n, 2)) - 1) * spd)
    p = leg.forward(theta)
    v = np.einsum("pij,pj->pi", leg.jacobian(theta), rates)
    dep = ({0, 1, 2} - set(free)).pop()
    ok = (
        within_limits(theta, leg.joint_limits)
        & (np.abs(rates[:, dep]) <= leg.speed_limits[dep])
        & (p[:, 1] <= p[:, 0])
        & np.all(v > 0, axis=1)
    )
    best_random = np.max(v[ok, 0] * v[ok, 1])
    assert result.raw[0] * result.raw[1] >= 0.98 * best_random
    v_check = leg.jacobian(result.theta) @ result.theta_dot
    np.testing.assert_allclose(v_check, result.raw, atol=1e-9)
    assert np.all(np.abs(result.theta_dot) <= leg.speed_limits + 1e-9)


def test_pinned_limits_are_used_as_given(params):
    lim = resolve_limits(params.robots["mst_m3f"], "mst_m3f")
    np.testing.assert_allclose(lim.position, [0.160, 0.064])
    np.testing.assert_allclose(lim.velocity, [0.80, 0.77])
    assert lim.position_source == lim.velocity_source == "pinned"


def test_derived_limits_are_reported_with_their_joint_state(params):
    lim = resolve_limits(params.robots["mst_q"], "mst_q", seed=1)
    summary = lim.summary()
    assert summary["Ppl_source"] == "derived"
    assert len(summary["Ppl_theta"]) == 3
    np.testing.assert_allclose(lim.position, 0.85 * np.asarray(summary["Ppl_raw"]))


def test_a_pinned_limit_the_leg_cannot_reach_is_an_infeasible_robot(raw_params):
    data = copy.deepcopy(raw_params)
    data["robots"]["mst_m3f"]["position_limit"]["pinned"] = {"x": 0.5, "z": 0.064}
    params = Params.model_validate(data)
    with pytest.raises(InfeasibleRobotError, match=r"position_limit.pinned: .* outside the leg"):
        resolve_limits(params.robots["mst_m3f"], "mst_m3f")


def test_pinned_mst_m3f_corner_is_reached_with_the_plate_parallel(params):
    leg = build_leg(params.robots["mst_m3f"].leg)
    raw = np.array([0.160, 0.064]) / 0.85  # the paper's raw (0.189, 0.074), rounded
    theta = leg.inverse(raw)
    np.testing.assert_allclose(leg.forward(theta), raw, atol=1e-12)
    assert within_limits(theta, leg.joint_limits)
