"""Experiment sweeps as queued DVC experiments (the plan, the queue's arguments and the reading of
its status are :mod:`ftfof.study.sweep`).

Each experiment sets every axis explicitly: ``dvc exp run`` keeps the workspace's params for the
next experiment, so a setting left out would leak from the previous one.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path

from ftfof.errors import FtfofError
from ftfof.pipeline import catalog
from ftfof.study.sweep import Experiment, failed, key_columns, queue_args, unfinished

# evaluate's DVC summary: the reference, and the optimum's Table I figures with their changes
SUMMARY = catalog.path("evaluate_summary").as_posix()


def dvc(*args: str) -> str:
    """Run ``dvc ARGS`` with this interpreter; its last error line becomes an FtfofError."""
    # `dvc queue start` spawns workers as `dvc`: they must find this environment's, not none
    bin_dir = str(Path(sys.executable).parent)
    env = {**os.environ, "PATH": os.pathsep.join([bin_dir, os.environ.get("PATH", "")])}
    code, stdout, stderr = output_of([sys.executable, "-m", "dvc", *args], env)
    if code != 0:
        message = (stderr or stdout).strip().splitlines()
        raise FtfofError(f"dvc {' '.join(args[:2])}", message[-1] if message else "failed")
    return stdout


def output_of(command: list[str], env: dict[str, str]) -> tuple[int, str, str]:
    """(exit code, stdout, stderr) of ``command`` once it exits. Its output goes to files, not
    pipes: `dvc queue start` leaves a daemon holding the output it inherited, and a pipe would
    stay open, and this call hang, until the last queue worker exits."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        code = subprocess.run(command, stdout=out, stderr=err, env=env).returncode
        out.seek(0)
        err.seek(0)
        return code, out.read(), err.read()


def run(
    experiments: Sequence[Experiment],
    jobs: int,
    poll: float,
    say: Callable[[str], None],
    wait: bool = True,
) -> str:
    """Queue ``experiments``, start ``jobs`` workers and, with ``wait``, return their key
    columns (:func:`key_columns`) once they are all done; a failed experiment is an error
    naming it."""
    names = [e.name for e in experiments]
    for experiment in experiments:
        dvc(*queue_args(experiment))
    dvc("queue", "start", "-j", str(jobs))
    say(f"sweep: queued {', '.join(names)}; {jobs} worker(s) started")
    if not wait:
        return ""
    told: list[str] = []  # a line when what it waits for changes, not one every poll
    while pending := unfinished(dvc("queue", "status"), names):
        if pending != told:
            say(f"sweep: waiting for {', '.join(pending)}")
            told = pending
        time.sleep(poll)
    if bad := failed(dvc("queue", "status"), names):
        raise FtfofError("sweep", f"failed: {', '.join(bad)} (see `dvc queue logs NAME`)")
    return key_columns(json.loads(dvc("exp", "show", "--json")), names, SUMMARY)
