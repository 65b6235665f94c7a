"""The pymoo problem: one batched evaluation whose constraints agree with the policy."""

import dataclasses

import numpy as np
import pytest

from ftfof.data.release import swing_gap
from ftfof.optimize.problem import TrajectoryProblem, asked_limits
from ftfof.surrogate.peaks import fit_peak_model
from ftfof.trajectory.sampling import sample_feasible


def _problem(ctx, surrogate, objectives=None):
    robot = ctx.robot
    return TrajectoryProblem(
        ctx.policy,
        surrogate,
        robot.objectives if objectives is None else objectives,
        ctx.rules,
    )


@pytest.fixture(params=["m3f", "mst_q"])
def ctx(request):
    return request.getfixturevalue(request.param)


def test_shapes_and_box(ctx, surrogate):
    problem = _problem(ctx, surrogate)
    assert problem.n_var == ctx.policy.n_free
    assert problem.n_obj == len(ctx.robot.objectives)
    assert all(not c.box for c in problem.rules)
    assert len(problem.rules) < len(ctx.policy.constraints)  # box rules are pymoo's bounds
    free = ctx.policy.lower + np.random.default_rng(0).random((9, problem.n_var)) * (
        ctx.policy.upper - ctx.policy.lower
    )
    out = problem.evaluate(free, return_as_dictionary=True)
    assert out["F"].shape == (9, problem.n_obj) and out["G"].shape == (9, problem.n_ieq_constr)
    assert np.all(np.isfinite(out["F"])) and np.all(np.isfinite(out["G"]))
    result = problem.evaluate_population(free)
    assert set(result.series) == set(surrogate.trained)
    for series in result.series.values():
        assert series.shape == (9, surrogate.seq_len) and np.all(series >= 0)
    foot = ctx.robot.foot
    film, clear = result.physical["film_safety"], result.physical["pad_clearance"]
    np.testing.assert_allclose(
        film, foot.film_min_bend_radius * result.series["curvature"].max(1) - 1
    )
    predicted = result.series["clearance"]
    gap = swing_gap(predicted, result.t, foot.swing_clearance, ctx.policy.timing.T2)
    np.testing.assert_allclose(
        clear, np.maximum(1 - predicted.max(1) / foot.swing_clearance, 1 - gap / 0.002)
    )
    retouch = result.physical["pad_retouch"]
    allowed = ctx.robot.retouch_allowed
    np.testing.assert_allclose(retouch, result.series["retouch"].max(1) / allowed - 1)
    limits = [film, clear, retouch]
    tolerance = ctx.robot.landing_tolerance
    if tolerance is None:  # MST-Q presses past a by design: no landing limit
        assert "landing_press" not in result.physical
    else:
        landing = np.abs(result.series["Fp"].max(1) - ctx.robot.pre_pressure)
        expected = landing / (tolerance * ctx.robot.pre_pressure) - 1
        np.testing.assert_allclose(result.physical["landing_press"], expected)
        limits.append(expected)
    if ctx.rules.proof_pull is None:  # MST-Q's proof pull is measured, not a rule
        assert "pad_holds" not in result.physical
    else:
        holds = 1 - result.series["holds"].max(1) / 0.5  # more likely than not it holds F_proof
        np.testing.assert_allclose(result.physical["pad_holds"], holds)
        limits.append(holds)
    # the physical limits are the last columns, in PHYSICAL's order
    np.testing.assert_allclose(out["G"][:, -len(limits) :], np.column_stack(limits))


@pytest.mark.parametrize("dropped", ["curvature", "clearance", "retouch", "Fp", "holds"])
def test_an_untrained_physical_target_is_no_constraint(m3f, surrogate, dropped):
    trained = tuple(n for n in surrogate.trained if n != dropped)
    untrained = dataclasses.replace(surrogate, trained=trained)
    problem = _problem(m3f, untrained)
    assert problem.n_ieq_constr == len(problem.rules) + 4 and len(problem.physical) == 4
    with pytest.raises(ValueError, match=dropped):
        untrained.predict(np.zeros((1, 32, 2)), np.zeros((1, 32, 2)), [dropped])


def test_constraints_agree_with_the_policy(ctx, surrogate):
    """Inside the box, the rule columns of G are <= 0 exactly when the policy calls the
    trajectory feasible (the last column is the predicted film safety)."""
    problem = _problem(ctx, surrogate)
    policy = ctx.policy
    feasible = policy.contract(sample_feasible(policy, 20, seed=5).X)
    rng = np.random.default_rng(1)
    random = policy.lower + rng.random((80, problem.n_var)) * (policy.upper - policy.lower)
    free = np.vstack([feasible, random])
    G = problem.evaluate(free, return_as_dictionary=True)["G"][:, : len(problem.rules)]
    expected = policy.check(policy.expand(free)).feasible
    np.testing.assert_array_equal(np.all(G <= 0, axis=1), expected)
    assert expected[:20].all() and not expected[20:].all()


def test_ties_are_honoured_in_every_decision_vector(mst_q, surrogate):
    problem = _problem(mst_q, surrogate)
    free = mst_q.policy.lower + 0.3 * (mst_q.policy.upper - mst_q.policy.lower)
    X = problem.evaluate_population(np.tile(free, (3, 1))).X
    # mst_q (FTFOF §VII, shape rules vertical): P10x = P11x = P12x and P3x = P4x = P5x = 0
    # decision order (bezier.DECISION_NAMES): P3x, P4x, P5x, P10x, P11x, P12x, P3z, ...
    np.testing.assert_array_equal(X[:, 3], X[:, 4])
    np.testing.assert_array_equal(X[:, 3], X[:, 5])
    np.testing.assert_array_equal(X[:, 0:3], 0.0)


def test_objectives_follow_the_priority_order(m3f, surrogate):
    problem = _problem(m3f, surrogate)
    free = m3f.policy.contract(sample_feasible(m3f.policy, 4, seed=2).X)
    F = problem.evaluate_population(free).F
    reversed_problem = _problem(m3f, surrogate, m3f.robot.objectives[::-1])
    np.testing.assert_allclose(reversed_problem.evaluate_population(free).F, F[:, ::-1])


def test_a_robot_asks_for_the_landing_press_retouch_and_hold_only_where_it_sets_them(m3f):
    neither = dataclasses.replace(
        m3f.rules, landing_tolerance=None, retouch_allowed=None, proof_pull=None
    )
    assert asked_limits(neither) == ("film_safety", "pad_clearance")
    both = dataclasses.replace(neither, landing_tolerance=0.1, retouch_allowed=0.5, proof_pull=6.6)
    assert asked_limits(both) == (
        "film_safety",
        "pad_clearance",
        "pad_retouch",
        "landing_press",
        "pad_holds",
    )


def test_the_peak_models_set_fs3_fs7_and_the_landing_limit(m3f, surrogate):
    """The search reads the GP's landing peak and eq. 16 total of each candidate's own control
    values (fs3 = |GP - a|), and the series keeps the GRU's shape."""
    policy = m3f.policy
    rng = np.random.default_rng(4)
    X = sample_feasible(policy, 30, seed=7).X
    peaks = {
        "Fp": fit_peak_model("Fp", X, 4.0 + 20.0 * X[:, 11] + rng.normal(0, 0.01, 30)),
        "jitter": fit_peak_model("jitter", X, 30.0 * X[:, 3]),
    }
    with_gps = dataclasses.replace(surrogate, peaks=peaks)
    free = policy.contract(X[:6])
    result = _problem(m3f, with_gps, ["fs3", "fs7", "fs1"]).evaluate_population(free)
    a = m3f.robot.pre_pressure
    np.testing.assert_allclose(result.F[:, 0], np.abs(peaks["Fp"](X[:6]) - a))
    np.testing.assert_allclose(result.F[:, 1], peaks["jitter"](X[:6]))
    landing = np.abs(peaks["Fp"](X[:6]) - a) / (m3f.robot.landing_tolerance * a) - 1
    np.testing.assert_allclose(result.physical["landing_press"], landing)
    plain = _problem(m3f, surrogate, ["fs3", "fs7", "fs1"]).evaluate_population(free)
    np.testing.assert_allclose(result.F[:, 2], plain.F[:, 2])  # the pull keeps the GRU's
    shape = plain.series["Fp"] / plain.series["Fp"].max(1, keepdims=True)
    np.testing.assert_allclose(result.series["Fp"], shape * peaks["Fp"](X[:6])[:, None])
