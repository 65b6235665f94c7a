"""The evaluation's pieces on synthetic frames: front sampling, failure policy, Table I rows."""

from __future__ import annotations

import pandas as pd
import pytest

from ftfof.errors import SimulationError
from ftfof.evaluate.run import OPTIMUM, Inputs, front_sample, ok_rows, table_rows


def _inputs(n: int, chosen: int, infeasible: tuple[int, ...] = ()) -> Inputs:
    front = pd.DataFrame(
        {"recheck_feasible": [i not in infeasible for i in range(n)]},
        index=pd.Index(range(n), name="row"),
    )
    return Inputs({"front_row": chosen}, front, ["fs1"], "digest")


def test_front_sample_spreads_over_passing_rows_and_leaves_out_the_optimum():
    inputs = _inputs(10, chosen=0, infeasible=(5,))
    rows = front_sample(inputs, 3)
    assert rows == [1, 6, 9]
    assert front_sample(inputs, 0) == []
    assert front_sample(inputs, 50) == [1, 2, 3, 4, 6, 7, 8, 9]


def _simulations(status: str = "ok") -> pd.DataFrame:
    peaks = {"peak_detachment": [2.0, 1.0], "peak_pre_pressure": [4.0, 2.0]}
    return pd.DataFrame(
        {
            "source": ["baseline:polynomial", OPTIMUM],
            "status": ["ok", status],
            "error": ["", "boom" if status != "ok" else ""],
            "peak_body_acc": [1.0, 1.0],
            **peaks,
        }
    )


def test_ok_rows_names_a_failed_optimum():
    with pytest.raises(SimulationError, match="boom"):
        ok_rows(_simulations("failed"), "polynomial")
    with pytest.raises(SimulationError, match="missing"):
        ok_rows(_simulations(), "cycloidal")


def test_table_rows_compare_the_optimum_with_the_reference():
    rows = {
        r.trajectory: r for r in table_rows(ok_rows(_simulations(), "polynomial"), "polynomial")
    }
    assert list(rows) == ["polynomial", OPTIMUM]
    assert rows[OPTIMUM].change["peak_detachment"] == pytest.approx(-50.0)
    assert rows["polynomial"].change["peak_pre_pressure"] == 0
