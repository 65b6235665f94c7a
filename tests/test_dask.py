"""Acquisition on a real Dask scheduler and worker on 127.0.0.1 equals the local pool (slow)."""

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from ftfof.sim import pool
from tests.conftest import ROOT
from tests.pipeline import pipeline_env
from tests.sim.helpers import bench

pytestmark = pytest.mark.slow


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _start(*args: str) -> subprocess.Popen:
    dask = str(Path(sys.executable).parent / "dask")
    return subprocess.Popen(
        [dask, *args],
        cwd=ROOT,
        env=pipeline_env(ROOT),
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


@pytest.fixture
def cluster():
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [_start("scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard")]
    try:
        procs.append(
            _start(
                "worker",
                address,
                "--nworkers",
                "1",
                "--nthreads",
                "1",
                "--no-dashboard",
                "--memory-limit",
                "0",
            )
        )
        from distributed import Client

        deadline = time.monotonic() + 120
        while True:
            try:
                with Client(address, timeout="5s") as client:
                    if client.scheduler_info()["workers"]:
                        break
            except OSError:
                pass
            assert time.monotonic() < deadline, "the Dask cluster did not come up"
            time.sleep(1)
        yield address
    finally:
        for p in procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGTERM)
        for p in procs:
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)


def test_eight_samples_on_dask_equal_the_local_pool(cluster, params, m3f):
    from ftfof.trajectory.sampling import sample_feasible

    X = sample_feasible(m3f.policy, 8, seed=11).X
    b = bench(params)
    specs = [b.bezier("sampled", i, x) for i, x in enumerate(X)]
    remote = {r.key: r for batch in pool.run_dask(specs, cluster, batch=2) for r in batch}
    local = {r.key: r for r in pool.run_all(specs, workers=2)}
    assert sorted(remote) == sorted(local) and len(remote) == 8
    for key, r in local.items():
        assert remote[key].ok and r.ok
        assert remote[key].scalars == r.scalars
        for name, series in r.channels.items():
            np.testing.assert_array_equal(remote[key].channels[name], series)
