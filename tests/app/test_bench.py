"""Bench and baselines built one way; control points parsed from a command line."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.errors import ParamsError
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench, parse_points


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


def test_parse_points_in_millimetres_and_its_errors():
    text = ",".join(str(v) for v in range(12))
    np.testing.assert_allclose(parse_points(text, "mm"), np.arange(12) * 1e-3)
    with pytest.raises(ParamsError, match="must be m or mm"):
        parse_points(text, "cm")
    with pytest.raises(ParamsError, match="needs 12 values"):
        parse_points("1,2", "m")
    with pytest.raises(ParamsError, match="12 comma-separated numbers"):
        parse_points("a," * 11 + "b", "m")
