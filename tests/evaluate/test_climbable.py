"""Which of Table I's trajectories the climbing robot is given: those it can run."""

from __future__ import annotations

import numpy as np

from ftfof.evaluate.feasible import climbable
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.sampling import sample_feasible


def test_runnable_trajectories_climb_and_the_others_are_named_with_two_rules(m3f):
    X = sample_feasible(m3f.policy, 1, seed=0).X[0]
    baseline = BezierTrajectory(m3f.policy, X)
    breaks = {"polynomial": ["a", "b", "c"], "eps_bezier": [], "optimum": []}
    runnable, skipped = climbable(
        m3f, {"polynomial": baseline, "eps_bezier": baseline}, {"optimum": X}, breaks
    )
    assert list(runnable) == ["eps_bezier", "optimum"]
    assert runnable["eps_bezier"] == (baseline, None)
    trajectory, row = runnable["optimum"]
    np.testing.assert_array_equal(row, X)
    assert isinstance(trajectory, BezierTrajectory)
    assert skipped == {"polynomial": "a; b"}
