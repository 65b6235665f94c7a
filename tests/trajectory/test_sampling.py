"""Sampling the climbable set: feasible, seeded, bounded."""

import math

import numpy as np
import pytest

from ftfof.errors import SamplingError
from ftfof.trajectory.policy import ConstraintPolicy
from ftfof.trajectory.sampling import sample_feasible


def test_samples_are_feasible_and_reproducible(m3f):
    a = sample_feasible(m3f.policy, 40, seed=7)
    b = sample_feasible(m3f.policy, 40, seed=7)
    c = sample_feasible(m3f.policy, 40, seed=8)
    assert a.X.shape == (40, 12)
    assert m3f.policy.check(a.X).feasible.all()
    np.testing.assert_array_equal(a.X, b.X)
    assert not np.array_equal(a.X, c.X)
    assert 0 < a.acceptance_rate < 1
    assert sum(a.rejected_by_kind.values()) >= a.draws - 40


def test_latin_hypercube_design_also_works(mst_q):
    res = sample_feasible(mst_q.policy, 30, seed=1, design="lhs")
    assert mst_q.policy.check(res.X).feasible.all()


def test_mst_q_samples_detach_vertically_and_honour_the_tie(mst_q):
    X = sample_feasible(mst_q.policy, 60, seed=3).X
    assert np.all(X[:, :3] == 0.0)
    assert np.all(X[:, 3] == X[:, 4]) and np.all(X[:, 4] == X[:, 5])


def test_too_small_a_draw_budget_is_a_clear_error_not_a_loop(m3f):
    with pytest.raises(SamplingError, match=r"only \d+ of 1000 .* raise sample.max_draws"):
        sample_feasible(m3f.policy, 1000, seed=0, batch=1024, max_draws=4096)


@pytest.mark.parametrize("robot", ["m3f", "mst_q"])
def test_every_accepted_row_passes_every_rule_at_1_khz(robot, request):
    ctx = request.getfixturevalue(robot)
    res = sample_feasible(ctx.policy, 50, seed=12)
    timing = ctx.robot.timing
    khz = ctx.policy.feasibility.model_copy(update={"n_t": math.ceil(timing.T3 * 1000) + 1})
    fine = ConstraintPolicy(ctx.robot, ctx.limits, khz, ctx.name)
    assert fine.t[1] - fine.t[0] <= 1e-3
    report = fine.check(res.X)
    assert report.feasible.all(), [report.failed(i) for i in np.flatnonzero(~report.feasible)]


@pytest.mark.parametrize("robot", ["m3f", "mst_q"])
def test_shaped_draws_pass_every_control_point_rule(robot, request):
    policy = request.getfixturevalue(robot).policy
    U = np.random.default_rng(0).random((20_000, policy.n_free))
    X, weight = policy.shaped(U)
    cheap = tuple(c for c in policy.constraints if not c.sampled)
    assert policy.check(X, constraints=cheap).feasible.all()
    np.testing.assert_array_equal(policy.shaped(U)[0], X)
    # the box weights estimate the fraction of the box those rules keep (4 binomial sigmas)
    box = policy.expand(policy.lower + U * (policy.upper - policy.lower))
    kept = policy.check(box, constraints=cheap).feasible.mean()
    assert abs(weight.mean() - kept) < 4 * math.sqrt(kept * (1 - kept) / len(U))


@pytest.mark.parametrize("robot", ["m3f", "mst_q"])
def test_every_accepted_row_is_one_the_leg_runs_at_1_khz(robot, request):
    """The controller export's joint check (each joint's range and speed, point by point) passes
    every sampled row: the foot's box and speed limits alone let about one row in eight of
    MST-M3F's outrun its knee or ankle."""
    from ftfof.evaluate.export import runnable
    from ftfof.trajectory.baselines import BezierTrajectory

    ctx = request.getfixturevalue(robot)
    for X in sample_feasible(ctx.policy, 30, seed=5).X:
        out = runnable(ctx, "row", BezierTrajectory(ctx.policy, X), None, 1000.0)
        assert out.within_joint_limits  # runnable refuses a row that outruns a joint
