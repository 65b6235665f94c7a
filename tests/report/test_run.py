"""A finished run's values in a notebook's shapes, from in-memory values (no files)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ftfof.report.run import Run
from ftfof.trajectory.bezier import DECISION_NAMES


def _run() -> Run:
    metrics = {
        "reference": "polynomial",
        "table": {
            "optimum": {"peak_pull": 6.0, "peak_pull_change": -25.0},
            "polynomial": {"peak_pull": 8.0, "peak_pull_change": 0.0},
        },
        "fidelity": {"fs1": {"spearman": 0.9}, "fs7": {"spearman": 0.7}},
    }
    rows = {n: [0.001 * k, 0.002 * k] for k, n in enumerate(DECISION_NAMES)}
    front = pd.DataFrame(
        {**rows, "fs1": [1.0, 2.0], "fs7": [3.0, 1.0]}, index=pd.Index([4, 9], name="row")
    )
    return Run({"front_row": 9}, front, metrics, pd.DataFrame())


def test_table_and_changes_split_the_figures_from_their_changes():
    run = _run()
    assert run.reference == "polynomial"
    assert run.objectives == ["fs1", "fs7"]
    assert run.table.loc["optimum", "peak_pull"] == 6.0
    assert list(run.table.columns) == ["peak_pull"]
    assert run.changes.loc["optimum", "peak_pull"] == -25.0
    assert run.fidelity.loc["fs7", "spearman"] == 0.7


def test_decision_is_the_optimum_row_unless_another_is_named():
    run = _run()
    np.testing.assert_allclose(run.decision(), 0.002 * np.arange(12))
    np.testing.assert_allclose(run.decision(4), 0.001 * np.arange(12))


def test_the_front_is_drawn_with_the_optimum_marked():
    assert _run().plot_front().axes
