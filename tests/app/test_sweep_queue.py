"""Sweeps as DVC experiments: the queue command sets every axis and the alias; the queue's
status is read for the sweep's own experiments only."""

from ftfof.pipeline.sweep import failed, queue_args, unfinished
from ftfof.study.sweep import parse_axes, plan


def test_an_experiment_is_queued_with_every_setting_and_its_alias():
    experiments = plan(parse_axes(["robots=mst_m3f,mst_q", "surfaces=acrylic,glass"]), "s1-")
    assert queue_args(experiments[3]) == [
        "exp", "run", "--queue", "-n", "s1-mst_q-glass", "-S", "robot=mst_q", "-S", "surface=glass",
        "-S", "train.alias=exp-s1-mst_q-glass",
    ]  # fmt: skip
    (seed,) = plan(parse_axes(["seeds=2"]))
    assert queue_args(seed)[-4:-2] == ["-S", "base.search_seed=2"]


STATUS = """Task     Name          Created    Status
0a1b2c3  mst_q-glass   10:02 AM   Running
4d5e6f7  mst_m3f-glass 10:02 AM   Queued
8a9b0c1  other         09:00 AM   Failed
2d3e4f5  mst_q-acryl   10:02 AM   Failed
Worker status: 1 active, 0 idle
"""


def test_queue_status_is_read_for_the_sweeps_own_experiments_only():
    names = ["mst_q-glass", "mst_m3f-glass", "mst_q-acryl"]
    assert unfinished(STATUS, names) == ["mst_q-glass", "mst_m3f-glass"]
    assert failed(STATUS, names) == ["mst_q-acryl"]


def test_a_command_returns_when_it_exits_though_a_daemon_it_left_holds_its_output():
    """`dvc queue start` leaves its workers holding the output it inherited: the call must not
    wait for them (it hung a sweep until the idle worker was killed)."""
    import os
    import sys
    import time

    from ftfof.pipeline.sweep import output_of

    sleeper = "import time; time.sleep(30)"
    daemon = f"import subprocess, sys; subprocess.Popen([sys.executable, '-c', {sleeper!r}]); "
    daemon += "print('started')"
    started = time.monotonic()
    code, out, err = output_of([sys.executable, "-c", daemon], dict(os.environ))
    assert (code, out.strip(), err) == (0, "started", "")
    assert time.monotonic() - started < 20  # not the daemon's 30 s
