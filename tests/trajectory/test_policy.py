"""The constraint policy: box, ties, named constraints and impossible robots."""

import copy

import numpy as np
import pytest

from ftfof.config import Params
from ftfof.errors import InfeasibleRobotError
from ftfof.pipeline.bench import context_of
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.feasibility import KINDS
from tests.conftest import PUBLISHED_M3F


def _with(**mm: float) -> np.ndarray:
    X = PUBLISHED_M3F.copy()
    for name, value in mm.items():
        X[DECISION_NAMES.index(name)] = value / 1000
    return X


def _mm(values: list[float]) -> np.ndarray:
    return np.asarray(values) / 1000


def test_published_m3f_optimum_is_feasible(m3f):
    report = m3f.policy.check(PUBLISHED_M3F)
    assert report.feasible[0], report.failed(0)


VIOLATORS = {
    "position_limit": _with(P10z=63.9, P11z=60.0),  # swing pushed over Pplz
    "min_detachment": _with(P5z=8.0, P3z=5.0, P4z=6.0),  # detachment ends below hd
    "transition": _mm([15.0, 28.5, 48.5, 95.5, 122.1, 133.0, 42.1, 39.6, 50.8, 20.2, 34.3, 9.8]),
    "shape": _with(P4z=30.0),  # P4 above P5: outside the upper triangle
    "bending": _mm([3.1, 6.7, 52.8, 110.2, 132.4, 137.9, 15.8, 25.4, 42.4, 27.6, 16.6, 12.0]),
    # inside the foot's box and speed limits, its landing outruns the knee by 11 %
    "joint_limit": _mm([0.3, 3.7, 10.5, 156.3, 154.9, 142.8, 43.3, 38.8, 44.5, 26.8, 40.3, 56.8]),
}


@pytest.mark.parametrize("kind", sorted(VIOLATORS))
def test_each_constraint_kind_rejects_its_violator_and_names_itself(m3f, kind):
    report = m3f.policy.check(VIOLATORS[kind])
    assert not report.feasible[0]
    failed = report.failed(0)
    kinds = {f.split(":")[0] for f in failed}
    if kind == "bending":  # a hairpin also outruns the leg's joints
        kinds.discard("joint_limit")
    assert kinds == {kind}, failed


def test_velocity_limit_rejects_a_too_fast_trajectory(raw_params):
    data = copy.deepcopy(raw_params)
    data["robots"]["mst_m3f"]["velocity_limit"]["pinned"] = {"x": 0.25, "z": 0.77}
    ctx = context_of(Params.model_validate(data))
    failed = ctx.policy.check(PUBLISHED_M3F).failed(0)  # its peak |vx| is 0.297 m/s
    assert [f.split(":")[0] for f in failed] == ["velocity_limit"]
    assert "|vx| <= Vplx" in failed[0]


def test_every_kind_is_represented(m3f):
    assert set(c.kind for c in m3f.policy.constraints) == set(KINDS)


def test_box_and_constraints_agree_on_the_box(m3f):
    pol = m3f.policy
    assert np.all(pol.lower < pol.upper)
    report = pol.check(pol.expand((pol.lower + pol.upper) / 2))
    box_rules = [
        j for j, c in enumerate(pol.constraints) if c.name.count("<") == 1 and not c.sampled
    ]
    assert np.all(report.violations[0, box_rules] <= 0)


def test_mst_q_ties_are_reparameterised_away(mst_q):
    pol = mst_q.policy
    assert pol.free_names == ("P10x", "P3z", "P4z", "P5z", "P10z", "P11z", "P12z")
    rng = np.random.default_rng(0)
    X = pol.expand(pol.lower + rng.random((50, pol.n_free)) * (pol.upper - pol.lower))
    col = {n: X[:, i] for i, n in enumerate(DECISION_NAMES)}
    assert np.all(col["P3x"] == 0) and np.all(col["P4x"] == 0) and np.all(col["P5x"] == 0)
    assert np.all(col["P10x"] == col["P11x"]) and np.all(col["P11x"] == col["P12x"])
    np.testing.assert_array_equal(pol.expand(pol.contract(X)), X)


def test_mst_q_adhesion_may_press_into_the_wall_down_to_press_depth(mst_q):
    pol = mst_q.policy
    i = pol.free_names.index("P12z")
    assert pol.lower[i] == pytest.approx(-mst_q.robot.shape.press_depth)


def _robot(raw_params, edit) -> Params:
    data = copy.deepcopy(raw_params)
    edit(data["robots"]["mst_m3f"])
    return Params.model_validate(data)


def test_landing_beyond_ppl_is_an_infeasible_robot(raw_params):
    params = _robot(raw_params, lambda r: r.update(landing={"x": 0.2, "z": 0.0}))
    with pytest.raises(InfeasibleRobotError) as err:
        context_of(params)
    assert "robots.mst_m3f.landing" in str(err.value)
    assert "landing beyond Ppl" in str(err.value)


def test_lower_bound_above_upper_names_the_variable_and_rules(raw_params):
    params = _robot(raw_params, lambda r: r["min_detachment"].update(hd=0.07))
    with pytest.raises(InfeasibleRobotError, match=r"P5z has no room: hd < P5z and P5z < Pplz"):
        context_of(params)


def test_md_height_is_one_and_a_half_bend_radii(params):
    foot = params.robots["mst_m3f"].foot
    assert params.robots["mst_m3f"].min_detachment.hd == pytest.approx(
        1.5 * foot.film_min_bend_radius
    )


def test_vertical_detachment_needs_zero_ld(raw_params):
    data = copy.deepcopy(raw_params)
    data["robot"] = "mst_q"
    data["robots"]["mst_q"]["min_detachment"]["ld"] = 0.002
    with pytest.raises(InfeasibleRobotError, match="vertical detachment needs ld = 0"):
        context_of(Params.model_validate(data))


def test_screen_agrees_with_full_check(m3f):
    rng = np.random.default_rng(3)
    pol = m3f.policy
    X = pol.expand(pol.lower + rng.random((4000, pol.n_free)) * (pol.upper - pol.lower))
    X = np.vstack([X, PUBLISHED_M3F])
    np.testing.assert_array_equal(pol.screen(X, chunk=97).feasible, pol.check(X).feasible)
