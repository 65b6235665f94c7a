"""Stage `acquire`: the dataset it writes, its metrics, resuming, and bad inputs."""

import json

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from ftfof.data.acquisition import ACQUISITION
from stages.cli import app
from tests.conftest import cli_args, write_params

pytestmark = pytest.mark.integration

runner = CliRunner()


@pytest.fixture(scope="module")
def acquired(tmp_path_factory, raw_params):
    tmp = tmp_path_factory.mktemp("acq")
    data = dict(raw_params)
    data["sample"] = {**raw_params["sample"], "n": 6}
    data["acquire"] = {**raw_params["acquire"], "workers": 2}
    params = write_params(tmp / "params.yaml", data)
    traj = tmp / "traj.parquet"
    assert (
        runner.invoke(
            app, ["sample", "-p", str(params), "--out", str(traj), "--metrics", str(tmp / "s.json")]
        ).exit_code
        == 0
    )
    out, metrics = tmp / "acq", tmp / "acq.json"
    args = cli_args(
        "acquire", params, trajectories=traj, out=out, metrics=metrics, timing=tmp / "timing.csv"
    )
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.stderr
    return tmp, params, traj, out, metrics, args


def test_acquire_writes_every_sample_and_baseline(acquired):
    tmp, _, _, out, metrics, _ = acquired
    table = pq.read_table(out / "samples.parquet")
    assert table.schema.equals(ACQUISITION, check_metadata=False)
    sources = table.column("source").to_pylist()
    assert sources.count("sampled") == 6
    assert {s for s in sources if s.startswith("baseline:")} == {
        "baseline:polynomial",
        "baseline:cycloidal",
        "baseline:random_bezier",
        "baseline:eps_bezier",
    }
    keys = table.column("key").to_pylist()
    assert keys == sorted(keys)  # canonical order, whatever the completion order
    assert not (out / "pending").exists()
    summary = json.loads(metrics.read_text())
    assert summary["samples"] == 10 and summary["failed"] == 0
    assert 0 < summary["seconds_per_sample"] < 30
    assert set(summary["baselines"]) == {"polynomial", "cycloidal", "random_bezier", "eps_bezier"}
    timing = (tmp / "timing.csv").read_text().splitlines()
    assert timing[0] == "key,status,wall_time" and len(timing) == 11
    fd = table.column("Fd").to_pylist()[0]
    assert len(fd) > 1000 and max(fd) > 0


def test_a_second_run_recomputes_the_same_dataset(acquired):
    _, _, _, out, _, args = acquired
    before = (out / "samples.parquet").read_bytes()
    result = runner.invoke(app, args)
    assert result.exit_code == 0
    assert "0 already done" in result.stderr  # a finished run leaves nothing to resume
    assert (out / "samples.parquet").read_bytes() == before


def test_trajectories_of_another_robot_are_refused(acquired, tmp_path):
    _, params, traj, _, _, _ = acquired
    table = pq.read_table(traj)
    other = table.set_column(1, "robot", pa.array(["mst_q"] * table.num_rows))
    path = tmp_path / "other.parquet"
    pq.write_table(other, path)
    result = runner.invoke(
        app,
        ["acquire", "-p", str(params), "--trajectories", str(path), "--out", str(tmp_path / "a")],
    )
    assert result.exit_code == 1
    assert "holds trajectories of ['mst_q']" in result.stderr
    assert not (tmp_path / "a").exists()


def test_a_truncated_trajectory_file_is_one_clear_error(acquired, tmp_path):
    _, params, traj, _, _, _ = acquired
    bad = tmp_path / "truncated.parquet"
    bad.write_bytes(traj.read_bytes()[:200])
    result = runner.invoke(
        app,
        ["acquire", "-p", str(params), "--trajectories", str(bad), "--out", str(tmp_path / "a")],
    )
    assert result.exit_code == 1
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "unreadable trajectory table" in lines[0]
    assert not (tmp_path / "a").exists()


def test_a_schema_mismatched_trajectory_file_names_the_column(acquired, tmp_path):
    _, params, traj, _, _, _ = acquired
    path = tmp_path / "renamed.parquet"
    pq.write_table(pq.read_table(traj).drop_columns(["P4z"]), path)
    result = runner.invoke(
        app,
        ["acquire", "-p", str(params), "--trajectories", str(path), "--out", str(tmp_path / "a")],
    )
    assert result.exit_code == 1
    assert "missing column 'P4z'" in result.stderr
