"""The refinement's stop rule: fidelity on the first priority *and* a front the simulator passes."""

import numpy as np

from ftfof.config import Optimize, RefineTarget
from ftfof.evaluate.fidelity import fidelity
from ftfof.optimize.select import rhs_ranking
from ftfof.pipeline.refine import Measured, nominees_of, round_target_met

S = np.array([[1.0], [2.0], [3.0], [4.0], [5.0]])
RANKED = fidelity(["fs1"], S * 1.01, S)[0]  # rho 1, 1 % off
TARGET = RefineTarget(spearman=0.9, relative_error=0.15, clean=0.9)


def test_fidelity_and_a_clean_front_stop_the_refinement():
    assert round_target_met(TARGET, RANKED, 0.01, clean=0.95)


def test_a_front_of_exploits_refines_on_even_when_fs1_ranks_well():
    assert not round_target_met(TARGET, RANKED, 0.01, clean=0.5)


def test_a_clean_front_ranked_badly_refines_on():
    reversed_ranks = fidelity(["fs1"], S[::-1], S)[0]
    assert not round_target_met(TARGET, reversed_ranks, 0.01, clean=1.0)
    assert not round_target_met(TARGET, RANKED, 0.5, clean=1.0)  # the optimum itself far off


def test_nominees_are_the_pools_pull_jitter_layers_in_rhs_order():
    cfg = Optimize()
    X1, F1 = np.arange(36.0).reshape(3, 12), np.array([[7.0, 9.0], [6.5, 4.0], [7.2, 3.0]])
    # round 2 simulated round 1's second point again (its optimum), and a better one
    X2, F2 = np.vstack([X1[1], X1[0] + 100]), np.array([[6.0, 3.0], [6.4, 3.5]])
    measured = [Measured(X1, F1, "refine:1"), Measured(X2, F2, "refine:2")]
    chosen = nominees_of(measured, 3, cfg)
    # the repeat counts once, with round 1's values (its 6.0 / 3.0 would have dominated all);
    # then the front of (6.4, 3.5) and (7.2, 3.0) in RHS order, then (6.5, 4.0), which (6.4, 3.5)
    # dominates although RHS over the whole pool would take it second
    np.testing.assert_array_equal(chosen.X, np.vstack([X2[1], X1[2], X1[1]]))
    assert chosen.origin == ["refine:2", "refine:1", "refine:1"]
    pool = np.vstack([F1, F2[1:]])
    assert rhs_ranking(pool, np.arange(4), cfg, 2) == [3, 1]  # what the layers prevent
    assert len(nominees_of(measured, 9, cfg).X) == 4
    assert nominees_of(measured, 0, cfg) is None
    # a trajectory the check refused (to the nanometre) is not nominated again, nor one with an
    # objective the simulation could not give
    refused = nominees_of(measured, 9, cfg, X2[1:] + 1e-10)
    np.testing.assert_array_equal(refused.X, np.vstack([X1[1], X1[2], X1[0]]))
    unknown = [Measured(X1, np.where(np.arange(3)[:, None] == 2, np.nan, F1), "refine:1")]
    np.testing.assert_array_equal(nominees_of(unknown, 9, cfg).X, X1[[1, 0]])
    assert nominees_of([Measured(np.empty((0, 12)), np.empty((0, 2)), "refine:1")], 3, cfg) is None
