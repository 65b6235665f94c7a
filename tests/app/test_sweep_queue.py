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
