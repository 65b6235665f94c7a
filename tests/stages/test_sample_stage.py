"""Stage `sample`: the Parquet table, its metrics, ties and its failure behaviour."""

import json

import numpy as np
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from ftfof.data.schema import TRAJECTORIES
from stages.cli import app
from tests.conftest import write_params

pytestmark = pytest.mark.integration

runner = CliRunner()


def _run(tmp_path, data):
    path = write_params(tmp_path / "params.yaml", data)
    out, metrics = tmp_path / "traj.parquet", tmp_path / "sample.json"
    result = runner.invoke(
        app, ["sample", "-p", str(path), "--out", str(out), "--metrics", str(metrics)]
    )
    return result, out, metrics


def test_sample_writes_the_documented_table_and_metrics(tmp_path, params_dict):
    params_dict["sample"]["n"] = 64
    result, out, metrics = _run(tmp_path, params_dict)
    assert result.exit_code == 0, result.stderr
    table = pq.read_table(out)
    assert table.schema.equals(TRAJECTORIES, check_metadata=False)
    assert table.num_rows == 64
    assert table.schema.field("P3x").metadata[b"unit"] == b"m"
    np.testing.assert_array_equal(table.column("sample_id").to_numpy(), np.arange(64))
    summary = json.loads(metrics.read_text())
    assert summary["samples"] == 64 and summary["robot"] == "mst_m3f"
    assert 0 < summary["acceptance_rate"] < 1
    assert summary["rejected_by_kind"]["velocity_limit"] > 0
    assert summary["rejected_by_fine_recheck"] >= 0 and summary["recheck_hz"] == 1000.0
    assert 0 < summary["box_acceptance_rate"] < summary["acceptance_rate"]


def test_sample_is_reproducible(tmp_path, params_dict):
    params_dict["sample"]["n"] = 16
    (a := tmp_path / "a").mkdir()
    (b := tmp_path / "b").mkdir()
    _, out_a, _ = _run(a, params_dict)
    _, out_b, _ = _run(b, params_dict)
    assert pq.read_table(out_a).equals(pq.read_table(out_b))


def test_mst_q_rows_detach_vertically_with_tied_adhesion(tmp_path, params_dict):
    params_dict["robot"] = "mst_q"
    params_dict["sample"]["n"] = 50
    result, out, _ = _run(tmp_path, params_dict)
    assert result.exit_code == 0, result.stderr
    t = pq.read_table(out).to_pandas()
    assert (t[["P3x", "P4x", "P5x"]] == 0).all().all()
    assert (t["P10x"] == t["P11x"]).all() and (t["P11x"] == t["P12x"]).all()
    assert (t["robot"] == "mst_q").all()


def test_impossible_robot_fails_before_writing_anything(tmp_path, params_dict):
    params_dict["robots"]["mst_m3f"]["landing"] = {"x": 0.2, "z": 0.0}
    result, out, metrics = _run(tmp_path, params_dict)
    assert result.exit_code == 2
    assert "landing beyond Ppl" in result.stderr
    assert not out.exists() and not metrics.exists()


def test_unreachable_sample_count_fails_cleanly(tmp_path, params_dict):
    params_dict["sample"].update(n=500, batch=1024, max_draws=2048)
    result, out, _ = _run(tmp_path, params_dict)
    assert result.exit_code == 1
    assert "raise sample.max_draws" in result.stderr
    assert not out.exists()
