"""`ftfof sweep robots=A,B surfaces=C,D seeds=1,2,3`: queue the product as DVC experiments, run
them in parallel workers, and print the `dvc exp show` table when they are done."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from stages.common import ParamsOption, console, stage


@stage
def command(
    axes: Annotated[
        list[str], typer.Argument(help="robots=NAME,..., surfaces=NAME,..., seeds=N,...")
    ],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    jobs: Annotated[int, typer.Option(min=1, help="Parallel queue workers.")] = 2,
    prefix: Annotated[str, typer.Option(help="Prefix of every experiment name.")] = "",
    wait: Annotated[bool, typer.Option(help="Wait for the queue and show the table.")] = True,
    poll: Annotated[float, typer.Option(min=0.1, help="Seconds between queue checks.")] = 5.0,
) -> None:
    """Queue one experiment per combination (`dvc exp run --queue`), start `jobs` workers."""
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.sweep import run
    from ftfof.study.sweep import check_presets, parse_axes, plan

    params = load_params(params_path)
    axes = parse_axes(axes)
    check_presets(axes, {"robot": list(params.robots), "surface": list(params.surfaces)})
    table = run(plan(axes, prefix), jobs, poll, console.print, wait)
    typer.echo(table, nl=False)
