"""The simulator's own repeatability: two perturbed runs per member and the rho between them."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ftfof.data.dataset import CHANNELS
from ftfof.data.targets import time_base
from ftfof.evaluate.repeat import HELD_PULL, REPEATS, repeat_specs, repeatability
from ftfof.evaluate.runs import OPTIMUM, split_runs
from ftfof.pipeline.bench import bench
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.sampling import sample_feasible


def test_each_member_runs_twice_off_by_the_repeatability_and_the_draws_are_seeded(params, m3f):
    X = sample_feasible(m3f.policy, 3, seed=4).X
    members = {10 + i: x for i, x in enumerate(X)}
    specs, controls = repeat_specs(bench(params, m3f), m3f.policy, members, 2e-4, seed=7)
    assert [(s.source, s.sample_id) for s in specs] == [
        (source, row) for row in members for source in REPEATS
    ]
    for spec in specs:
        off = (
            m3f.policy.contract(controls[spec.key])[0]
            - m3f.policy.contract(members[spec.sample_id])[0]
        )
        assert 0 < np.abs(off).max() < 5 * 2e-4  # off, by about the repeatability
    _, same = repeat_specs(bench(params, m3f), m3f.policy, members, 2e-4, seed=7)
    assert all(np.array_equal(controls[k], same[k]) for k in controls)
    _, other = repeat_specs(bench(params, m3f), m3f.policy, members, 2e-4, seed=8)
    assert not any(np.array_equal(controls[k], other[k]) for k in controls)


def _runs(policy, pulls: list[list[float]], held: list[list[float]]) -> pd.DataFrame:
    """Two repeatability runs per member: a pull bump of each height, over the real time base."""
    T3 = policy.timing.T3
    t = np.arange(-0.2, T3 + 0.3, 1e-3)
    X = sample_feasible(policy, len(pulls[0]), seed=1).X
    rows = []
    for source, heights, holds in zip(REPEATS, pulls, held, strict=True):
        for row, (p, h) in enumerate(zip(heights, holds, strict=True)):
            bump = p * np.exp(-(((t - 0.5 * T3) / 0.02) ** 2))
            channels = {c: np.zeros_like(t) for c in CHANNELS}
            channels.update(
                t=t,
                Fx_pad=0.6 * bump,
                Fz_pad=0.8 * bump,
                bonds=np.where(t < 0.6 * T3, 10.0, 0.0),
                switch=(t > 0.6 * T3).astype(float),
                body_acc=1.0 + bump,
            )
            rows.append(
                {
                    "source": source,
                    "sample_id": row,
                    "status": "ok",
                    HELD_PULL: h,
                    **dict(zip(DECISION_NAMES, X[row], strict=True)),
                    **channels,
                }
            )
    return pd.DataFrame(rows)


def test_the_bound_is_the_rank_correlation_between_the_two_runs(m3f):
    policy = m3f.policy
    force_t = time_base(policy.timing.T3, 0.25, 64)
    same = _runs(policy, [[1.0, 2.0, 3.0, 4.0]] * 2, [[5.0, 6.0, 4.0, 7.0]] * 2)
    bound = repeatability(["fs1"], policy, same, force_t, 0.25, 5.0)
    assert bound == {"fs1": {"n": 4, "spearman": 1.0}, HELD_PULL: {"n": 4, "spearman": 1.0}}
    noisy = _runs(
        policy, [[1.0, 2.0, 3.0, 4.0], [2.0, 1.0, 4.0, 3.0]], [[5, 6, 4, 7], [7, 4, 6, 5]]
    )
    bound = repeatability(["fs1"], policy, noisy, force_t, 0.25, 5.0)
    assert bound["fs1"]["spearman"] == pytest.approx(0.6)
    assert bound[HELD_PULL]["spearman"] == pytest.approx(-0.6)


def test_a_member_with_a_failed_run_is_left_out_and_no_runs_give_no_bound(m3f):
    policy = m3f.policy
    force_t = time_base(policy.timing.T3, 0.25, 64)
    runs = _runs(policy, [[1.0, 2.0, 3.0, 4.0]] * 2, [[5.0, 6.0, 4.0, 7.0]] * 2)
    runs.loc[(runs.source == REPEATS[1]) & (runs.sample_id == 2), "status"] = "failed"
    assert repeatability(["fs1"], policy, runs, force_t, 0.25, 5.0)["fs1"]["n"] == 3
    assert repeatability(["fs1"], policy, runs.iloc[:0], force_t, 0.25, 5.0) is None


def test_the_repeatability_runs_stay_out_of_the_table_and_the_checks():
    sources = [OPTIMUM, "front", "fine:optimum", "film:front", *REPEATS]
    frame = pd.DataFrame({"source": sources, "sample_id": range(len(sources))})
    at_step, fine, film, repeats = split_runs(frame)
    assert list(at_step.source) == [OPTIMUM, "front"]
    assert list(fine.source) == [OPTIMUM] and list(film.source) == ["front"]
    assert list(repeats.source) == list(REPEATS)
