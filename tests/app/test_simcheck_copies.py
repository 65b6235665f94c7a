"""The simulator check's perturbed copies: the robot's error, not a draw kept inside the box."""

from __future__ import annotations

import numpy as np

from ftfof.pipeline.simcheck import perturbed_runs
from ftfof.robot import RobotContext
from ftfof.trajectory.bezier import DECISION_NAMES


def test_copies_of_a_row_on_a_bound_go_both_ways_and_fixed_values_stay(
    m3f: RobotContext, mst_q: RobotContext
):
    policy = m3f.policy
    p3x = DECISION_NAMES.index("P3x")
    row = policy.expand(0.5 * (policy.lower + policy.upper))[0]
    row[p3x] = policy.lower[policy.free_names.index("P3x")]  # a peel straight up: P3x = P0x
    runs = perturbed_runs(policy, row, 2e-4, 400, np.random.default_rng(1))
    assert np.array_equal(runs[0], row)
    off = np.array(runs[1:]) - row
    below = np.mean(off[:, p3x] < 0.0)
    assert 0.4 < below < 0.6  # clipped, none would go below the bound and half would not move
    assert 1.5e-4 < np.std(off[:, p3x]) < 2.5e-4

    q = mst_q.policy  # vertical detachment: P3x = P4x = P5x = P0x are fixed, not free
    row = q.expand(0.5 * (q.lower + q.upper))[0]
    runs = np.array(perturbed_runs(q, row, 2e-4, 20, np.random.default_rng(2)))
    fixed = [DECISION_NAMES.index(n) for n in ("P3x", "P4x", "P5x")]
    assert np.all(runs[:, fixed] == row[fixed])
    assert np.all(np.abs(runs[1:] - row).max(axis=1) > 0.0)
