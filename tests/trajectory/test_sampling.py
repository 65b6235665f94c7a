"""Sampling the climbable set: feasible, seeded, bounded."""

import numpy as np
import pytest

from ftfof.errors import SamplingError
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
