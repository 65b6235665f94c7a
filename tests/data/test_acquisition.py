"""An acquisition's planning and checks without simulating: the specs of a trajectory table,
a finished job's rows in key order, its completeness and failure rate."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pytest

from ftfof.data.acquisition import canonical_rows, check_complete, check_failures, sampled_specs
from ftfof.errors import DataError, SimulationError
from ftfof.pipeline.bench import bench, context_of
from ftfof.trajectory.bezier import DECISION_NAMES
from tests.conftest import PUBLISHED_M3F


def _trajectories(robot: str, rows: int = 3) -> pa.Table:
    X = PUBLISHED_M3F + 1e-4 * np.arange(rows)[:, None]
    columns = {n: X[:, j] for j, n in enumerate(DECISION_NAMES)}
    return pa.table({"sample_id": np.arange(10, 10 + rows), "robot": [robot] * rows, **columns})


def test_a_trajectory_tables_rows_become_sampled_specs_with_their_decisions(params):
    on = bench(params, context_of(params))
    specs, controls = sampled_specs(on, _trajectories("mst_m3f"), "mst_m3f", "t.parquet", 2)
    assert [s.key for s in specs] == ["sampled:10", "sampled:11"]
    assert {s.source for s in specs} == {"sampled"} and list(controls) == [
        "sampled:10",
        "sampled:11",
    ]
    np.testing.assert_array_equal(controls["sampled:11"], PUBLISHED_M3F + 1e-4)


def test_another_robots_trajectories_are_refused(params):
    on = bench(params, context_of(params))
    with pytest.raises(DataError, match=r"holds trajectories of \['mst_q'\] but params select"):
        sampled_specs(on, _trajectories("mst_q"), "mst_m3f", "t.parquet")


def _finished(status: list[str], keys: list[str] | None = None) -> pa.Table:
    keys = keys or [f"k{i}" for i in range(len(status))]
    errors = ["" if s == "ok" else f"{k} diverged" for k, s in zip(keys, status, strict=True)]
    return pa.table({"key": keys, "status": status, "error": errors})


def test_a_jobs_rows_are_its_own_keys_in_key_order_whatever_the_completion_order():
    """Parts finish in any order and a pending area may hold another run's samples: the job's
    table is its own rows, sorted by key, so that equal runs write equal files."""
    table = pa.table({"key": ["s:3", "other:0", "s:1", "s:2"], "status": ["a", "b", "c", "d"]})
    rows = canonical_rows(table, {"s:1", "s:2", "s:3", "s:9"})
    assert rows.column("key").to_pylist() == ["s:1", "s:2", "s:3"]
    assert rows.column("status").to_pylist() == ["c", "d", "a"]


def test_a_finished_job_holds_each_expected_sample_once():
    check_complete(_finished(["ok", "ok"]), 2, "out")
    with pytest.raises(SimulationError, match="expected 3 distinct samples, found 2"):
        check_complete(_finished(["ok", "ok"]), 3, "out")
    with pytest.raises(SimulationError, match="expected 2 distinct samples, found 1"):
        check_complete(_finished(["ok", "ok"], ["a", "a"]), 2, "out")


def test_more_failures_than_the_rate_allows_name_the_first_errors():
    table = _finished(["ok", "failed", "ok", "failed"])
    check_failures(table, 0.5)
    with pytest.raises(SimulationError, match=r"2 of 4 samples failed \(50.0% > .* 40.0%\)") as err:
        check_failures(table, 0.4)
    assert "['k1 diverged', 'k3 diverged']" in str(err.value)
