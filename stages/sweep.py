"""`ftfof sweep robots=A,B surfaces=C,D`: queue the product as DVC experiments, run them in
parallel workers, and print the `dvc exp show` table when they are done."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path
from typing import Annotated

import typer

from stages.common import ParamsOption, console, stage


@stage
def command(
    axes: Annotated[list[str], typer.Argument(help="robots=NAME,... and/or surfaces=NAME,...")],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    jobs: Annotated[int, typer.Option(min=1, help="Parallel queue workers.")] = 2,
    prefix: Annotated[str, typer.Option(help="Prefix of every experiment name.")] = "",
    wait: Annotated[bool, typer.Option(help="Wait for the queue and show the table.")] = True,
    poll: Annotated[float, typer.Option(min=0.1, help="Seconds between queue checks.")] = 5.0,
) -> None:
    """Queue one experiment per combination (`dvc exp run --queue`), start `jobs` workers."""
    from ftfof.errors import FtfofError
    from ftfof.pipeline.sweep import check_presets, failed, parse_axes, plan, unfinished
    from stages.params import load_params

    params = load_params(params_path)
    axes = parse_axes(axes)
    check_presets(axes, {"robot": list(params.robots), "surface": list(params.surfaces)})
    experiments = plan(axes, prefix)
    names = [e.name for e in experiments]
    for experiment in experiments:
        _dvc(*experiment.queue_args())
    _dvc("queue", "start", "-j", str(jobs))
    console.print(f"sweep: queued {', '.join(names)}; {jobs} worker(s) started")
    if not wait:
        return
    while pending := unfinished(_dvc("queue", "status"), names):
        console.print(f"sweep: waiting for {', '.join(pending)}")
        time.sleep(poll)
    console.print(_dvc("exp", "show", "--no-pager"))
    if bad := failed(_dvc("queue", "status"), names):
        raise FtfofError("sweep", f"failed: {', '.join(bad)} (see `dvc queue logs NAME`)")


def _dvc(*args: str) -> str:
    from ftfof.errors import FtfofError

    result = subprocess.run([sys.executable, "-m", "dvc", *args], capture_output=True, text=True)
    if result.returncode != 0:
        message = (result.stderr or result.stdout).strip().splitlines()
        raise FtfofError(f"dvc {' '.join(args[:2])}", message[-1] if message else "failed")
    return result.stdout
