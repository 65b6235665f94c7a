"""Bad input a new user typed: one clear line naming what and where, a non-zero exit, and nothing
written; an interrupted command says what it kept and how to go on."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from stages.cli import app
from stages.common import INTERRUPTED, interrupted
from tests.conftest import PUBLISHED_M3F, ROOT, cli_args, write_params

runner = CliRunner()
PARAMS = ROOT / "params.yaml"


def _points(X: np.ndarray) -> str:
    return ",".join(f"{v:g}" for v in X)


def _simulate(tmp_path, X, *extra: str):
    args = cli_args("simulate", PARAMS, points=_points(X), out_dir=tmp_path / "out")
    return runner.invoke(app, [*args, *extra])


def test_points_the_robot_cannot_run_are_refused_naming_the_rule(tmp_path):
    X = PUBLISHED_M3F.copy()
    X[7] = -0.01  # P4z ten millimetres into the wall
    result = _simulate(tmp_path, X)
    assert result.exit_code == 2  # a params error
    assert "mst_m3f cannot run them" in result.stderr and "--allow-infeasible" in result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.integration
def test_allowed_infeasible_points_are_simulated_under_a_marked_name(tmp_path):
    X = PUBLISHED_M3F.copy()
    X[7] = -0.01
    result = _simulate(tmp_path, X, "--allow-infeasible")
    assert "infeasible for mst_m3f" in result.output
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == ["points-infeasible.csv", "points-infeasible.png"]


@pytest.mark.parametrize(
    ("command", "out"), [("simulate", "out_dir"), ("export", "out"), ("climb", "out_dir")]
)
def test_a_nan_or_infinite_control_value_is_named_as_such(tmp_path, command, out):
    """Not as a shape rule it breaks (`P15x < P11x ...`), for every command taking --points."""
    X = [f"{v:g}" for v in PUBLISHED_M3F]
    X[1], X[11] = "nan", "-inf"
    args = cli_args(command, PARAMS, points=",".join(X), **{out: tmp_path / "out"})
    result = runner.invoke(app, args)
    assert result.exit_code == 2
    assert result.stderr.strip().splitlines() == [
        "error: --points: P4x is nan, P12z is -inf: every control value must be finite"
    ]
    assert not (tmp_path / "out").exists()


def test_points_in_millimetres_without_the_unit_are_refused_with_the_fix(tmp_path):
    result = _simulate(tmp_path, 1000 * PUBLISHED_M3F)
    assert result.exit_code == 2 and "they look like millimetres (add --unit mm)" in result.stderr
    result = _simulate(tmp_path, PUBLISHED_M3F, "--unit", "mm")
    assert result.exit_code == 2 and "they look like metres (drop --unit mm)" in result.stderr
    assert not (tmp_path / "out").exists()


def test_a_log_whose_time_unit_is_off_by_a_thousand_is_refused(tmp_path):
    t = np.linspace(0.0, 1.5, 200)  # seconds, under a header that says milliseconds
    log = tmp_path / "run1.csv"
    x, z = 20 * t, 10 * np.sin(np.pi * t / 1.5)  # mm
    pd.DataFrame({"t [ms]": t, "x": x, "z": z, "Fz": np.sin(t)}).to_csv(log, index=False)
    result = runner.invoke(app, ["import-logs", str(log), "--out", str(tmp_path / "imp")])
    assert result.exit_code == 1
    assert "column 't [ms]': the log spans 0.0015 s" in result.stderr
    assert not (tmp_path / "imp").exists()
    # the right time unit, but the positions in micrometres read as millimetres
    pd.DataFrame({"t": t, "x [mm]": 1000 * x, "z": z, "Fz": np.sin(t)}).to_csv(log, index=False)
    result = runner.invoke(app, ["import-logs", str(log), "--out", str(tmp_path / "imp")])
    assert result.exit_code == 1 and "check the length and time units" in result.stderr
    assert not (tmp_path / "imp").exists()


def test_acquire_refuses_a_limit_below_one(tmp_path):
    args = cli_args("acquire", PARAMS, limit=-1, out=tmp_path / "acq")
    result = runner.invoke(app, args)
    assert result.exit_code == 2 and "--limit" in result.output
    assert not (tmp_path / "acq").exists()


@pytest.mark.parametrize("workers", [0, -3])
@pytest.mark.parametrize("command", ["acquire", "refine", "polish", "evaluate"])
def test_workers_below_one_are_refused_before_anything_is_written(tmp_path, command, workers):
    """--workers is a count; all cores is acquire.workers 0 in the params (acquire wrote its
    manifest, then failed in the pool with a raw ValueError)."""
    args = cli_args(command, PARAMS, workers=workers, out=tmp_path / "out")
    result = runner.invoke(app, [*args, *(["--limit", "2"] if command == "acquire" else [])])
    said = "Invalid value for '--workers': Input should be greater than or equal to 1"
    assert result.exit_code == 2 and said in result.output
    assert not list(tmp_path.iterdir())


def test_export_refuses_a_rate_beyond_its_bound_in_one_line_at_once(tmp_path):
    out = tmp_path / "polynomial.csv"
    args = cli_args("export", PARAMS, baseline="polynomial", rate="1e9", out=out)
    started = time.monotonic()
    result = runner.invoke(app, args)
    assert result.exit_code == 2 and time.monotonic() - started < 30  # not a billion rows
    assert result.stderr.strip().splitlines() == [
        "error: --rate: export rate 1e+09 Hz is beyond the bound of 100000 Hz (a controller's "
        "loop runs at 1-10 kHz)"
    ]
    assert not out.exists()


def test_a_missing_input_names_the_stage_that_writes_it(tmp_path):
    missing = tmp_path / "data" / "polish" / "optimize"
    args = cli_args("evaluate", PARAMS, optimize=missing, out=tmp_path / "eval")
    result = runner.invoke(app, args)
    assert result.exit_code == 1
    assert "no optimum (run `ftfof polish` first)" in result.stderr
    models = tmp_path / "data" / "refine" / "models"
    args = cli_args("polish", PARAMS, optimize=missing.parent.parent / "refine" / "optimize")
    result = runner.invoke(app, [*args, "--models", str(models), "--out", str(tmp_path / "p")])
    assert "no optimum (run `ftfof refine` first)" in result.stderr
    assert not (tmp_path / "eval").exists() and not (tmp_path / "p").exists()


def test_an_interrupt_says_what_was_kept():
    assert interrupted("acquire") == (
        "interrupted: its finished simulations are kept (data/acquisition/pending); "
        "run `ftfof acquire` again to resume"
    )
    assert "nothing was written" in interrupted("train")
    assert "(/tmp/p/journal.jsonl)" in interrupted("polish", Path("/tmp/p"))


@pytest.mark.integration
@pytest.mark.parametrize(
    ("stop", "workers"), [(signal.SIGTERM, 1), (signal.SIGINT, 2)], ids=["sigterm", "ctrl-c"]
)
def test_a_stop_ends_acquire_with_a_word_and_a_rerun_resumes(tmp_path, raw_params, stop, workers):
    """A scheduler's SIGTERM, or Ctrl-C sent to the whole process group (workers too),
    mid-acquisition: one line on stderr, exit 130, finished parts kept and none of them a sample
    failed by the stop; the same command again simulates only what is left."""
    data = {**raw_params, "sample": {**raw_params["sample"], "n": 12}}
    data["acquire"] = {**raw_params["acquire"], "workers": workers, "batch": 1}
    params = write_params(tmp_path / "params.yaml", data)
    traj, out = tmp_path / "traj.parquet", tmp_path / "acq"
    sample = cli_args("sample", params, out=traj, metrics=tmp_path / "s.json")
    assert runner.invoke(app, sample).exit_code == 0
    cmd = [sys.executable, "-m", "ftfof", *cli_args("acquire", params, trajectories=traj, out=out)]
    cmd += ["--metrics", str(tmp_path / "a.json"), "--timing", str(tmp_path / "t.csv")]
    env = {**os.environ, "MLFLOW_TRACKING_URI": f"sqlite:///{tmp_path / 'mlflow.db'}"}
    proc = subprocess.Popen(
        cmd,
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    deadline = time.monotonic() + 120
    while not list((out / "pending").glob("part-*.parquet")) and time.monotonic() < deadline:
        time.sleep(0.2)
    if stop == signal.SIGINT:
        os.killpg(proc.pid, stop)  # as a terminal's Ctrl-C: the whole group
    else:
        proc.send_signal(stop)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == INTERRUPTED, err.decode()
    assert "interrupted: its finished simulations are kept" in err.decode()
    parts = list((out / "pending").glob("part-*.parquet"))
    kept = sum(pq.read_metadata(p).num_rows for p in parts)
    statuses = [
        s for p in parts for s in pq.read_table(p, columns=["status"]).column(0).to_pylist()
    ]
    assert set(statuses) == {"ok"}  # no sample was failed by the stop
    assert kept >= 1 and f"kept ({out / 'pending'})" in err.decode()
    again = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    assert f"{kept} already done" in again.stdout + again.stderr
