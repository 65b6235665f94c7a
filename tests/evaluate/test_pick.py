"""Which trajectory a command runs: a baseline by name, typed points, or a row of the front."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ftfof.errors import ParamsError
from ftfof.evaluate.pick import front_row, named_baseline, typed_points
from ftfof.evaluate.run import Inputs
from ftfof.pipeline.bench import baseline_trajectories
from ftfof.trajectory.bezier import DECISION_NAMES
from tests.conftest import PUBLISHED_M3F


def test_a_baseline_by_name_is_analytic_and_an_unknown_one_names_the_others(params, m3f):
    baselines = baseline_trajectories(params, m3f)
    name, trajectory, X, extra = named_baseline(baselines, "cycloidal")
    assert (name, trajectory, X) == ("cycloidal", baselines["cycloidal"], None)
    assert "not checked" in extra["constraint_policy"]
    with pytest.raises(ParamsError, match=r"unknown baseline 'spline' \(have polynomial"):
        named_baseline(baselines, "spline")


def test_typed_points_are_the_robots_bezier(m3f):
    name, trajectory, X, extra = typed_points(m3f, list(PUBLISHED_M3F))
    assert name == "points" and extra == {}
    np.testing.assert_array_equal(X, PUBLISHED_M3F)
    np.testing.assert_allclose(trajectory.sample(np.array([0.0])).position[0, 0], [0.0, 0.0])


def _inputs() -> Inputs:
    rows = [3, 5]
    front = pd.DataFrame(
        [PUBLISHED_M3F, PUBLISHED_M3F * 1.01], columns=list(DECISION_NAMES), index=rows
    ).assign(origin=["front", "polished"])
    return Inputs({"front_row": 5, "models_digest": "m"}, front, ["fs1"], "o")


def test_a_front_row_or_by_default_the_optimum_with_where_it_came_from(m3f):
    name, _, X, extra = front_row(m3f, _inputs(), None, Path("data/polish/optimize"))
    assert name == "optimum" and extra == {
        "front_row": 5,
        "origin": "polished",
        "optimum_digest": "o",
        "models_digest": "m",
    }
    np.testing.assert_array_equal(X, PUBLISHED_M3F * 1.01)
    name, _, X, extra = front_row(m3f, _inputs(), 3, Path("o"))
    assert name == "row3" and extra["origin"] == "front"
    with pytest.raises(ParamsError, match=r"7 is not a row of data/opt \(0..5\)"):
        front_row(m3f, _inputs(), 7, Path("data/opt"))
