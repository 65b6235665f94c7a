"""A killed acquisition resumes: exactly the samples of an uninterrupted run, none lost (slow)."""

import os
import signal
import subprocess
import sys
import time

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from tests.conftest import ROOT, cli_args, write_params
from tests.pipeline import pipeline_env

pytestmark = pytest.mark.slow
N = 40


def _setup(tmp, raw_params):
    data = dict(raw_params)
    data["sample"] = {**raw_params["sample"], "n": N}
    data["acquire"] = {**raw_params["acquire"], "workers": 2, "batch": 2, "baselines": False}
    params = write_params(tmp / "params.yaml", data)
    traj = tmp / "traj.parquet"
    _ftfof(tmp, "sample", "-p", str(params), "--out", str(traj), "--metrics", str(tmp / "s.json"))
    return cli_args(
        "acquire",
        params,
        trajectories=traj,
        out=tmp / "acq",
        metrics=tmp / "acq.json",
        timing=tmp / "timing.csv",
    )


def _ftfof(cwd, *args, **kw):
    return subprocess.run(
        [sys.executable, "-m", "ftfof", *args],
        cwd=cwd,
        env=pipeline_env(ROOT),
        capture_output=True,
        text=True,
        timeout=600,
        check=True,
        **kw,
    )


def _table(tmp):
    return pq.read_table(tmp / "acq" / "samples.parquet")


def test_a_killed_acquisition_resumes_without_losing_or_duplicating(tmp_path, raw_params):
    killed, clean = tmp_path / "killed", tmp_path / "clean"
    killed.mkdir()
    clean.mkdir()
    args = _setup(killed, raw_params)
    proc = subprocess.Popen(
        [sys.executable, "-m", "ftfof", *args],
        cwd=killed,
        env=pipeline_env(ROOT),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    pending = killed / "acq" / "pending"
    deadline = time.monotonic() + 300
    try:
        while time.monotonic() < deadline and len(list(pending.glob("part-*.parquet"))) < 3:
            assert proc.poll() is None, "the run finished before it could be killed"
            time.sleep(0.2)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    parts = list(pending.glob("part-*.parquet"))
    assert 3 <= len(parts) < N // 2
    assert not (killed / "acq" / "samples.parquet").exists()

    resumed = _ftfof(killed, *args)
    assert f"{N} samples, " in resumed.stderr and "already done" in resumed.stderr
    _ftfof(clean, *_setup(clean, raw_params))
    a, b = _table(killed), _table(clean)
    keys = a.column("key").to_pylist()
    assert len(keys) == len(set(keys)) == N
    assert _bytes(a) == _bytes(b)  # NaN-aware: a pad that never detaches has no switch time


def _bytes(table) -> bytes:
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    return sink.getvalue().to_pybytes()
