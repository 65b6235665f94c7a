"""Sweeps as DVC experiments: a dvc command's output is read once it exits."""


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


def test_a_waiting_sweep_says_so_when_what_it_waits_for_changes(monkeypatch):
    """A sweep polls every few seconds for half an hour: one line per poll buried its log."""
    from ftfof.pipeline import sweep
    from ftfof.study.sweep import Experiment

    statuses = iter(
        ["a Running\nb Queued"] * 3 + ["a Success\nb Running"] * 2 + ["a Success\nb Success"] * 2
    )

    def dvc(*args):
        if args[:2] == ("queue", "status"):
            return next(statuses)
        return "[]" if args[:2] == ("exp", "show") else ""

    monkeypatch.setattr(sweep, "dvc", dvc)
    said: list[str] = []
    experiments = [Experiment("a", {}), Experiment("b", {})]
    sweep.run(experiments, 1, 0.0, said.append)
    assert said == [
        "sweep: queued a, b; 1 worker(s) started",
        "sweep: waiting for a, b",
        "sweep: waiting for b",
    ]
