"""The baselines' specs on a bench."""

from __future__ import annotations

from ftfof.pipeline.bench import baseline_trajectories, bench
from ftfof.sim.spec import baseline_specs


def test_baseline_specs_key_every_baseline_in_the_order_asked(params, m3f):
    assert params.robot == "mst_m3f"
    ctx = m3f  # the session's context for params' robot (building one costs seconds)
    trajectories = baseline_trajectories(params, ctx)
    on = bench(params, ctx)
    assert [s.key for s in baseline_specs(on, trajectories)] == [
        s.key for s in baseline_specs(on, trajectories, list(trajectories))
    ]
    names = list(trajectories)[::-1][:2]
    specs = baseline_specs(on, trajectories, names)
    assert [s.source for s in specs] == [f"baseline:{n}" for n in names]
