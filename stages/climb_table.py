"""Stage `climb`: Table I's trajectories the robot can run, and the chosen optimum, on the
whole climbing robot -> data/climb (each climb's files) and reports/climb.json (the table).

The climbs are resumable (:func:`ftfof.pipeline.climb.climb_all`); `ftfof climb` climbs one
trajectory by hand.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, WorkersOption, console, stage

OPTIMIZE = path("polish_optimize")
OUT = path("climbs_table")
RECORD = path("climb_table")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    optimize: Annotated[Path, typer.Option(help="The optimum and its front.")] = OPTIMIZE,
    out: Annotated[Path, typer.Option(help="Where each climb's files go.")] = OUT,
    record: Annotated[Path, typer.Option(help="The climbing table (JSON).")] = RECORD,
    workers: Annotated[int | None, WorkersOption] = None,
) -> None:
    """Climb every Table I trajectory the robot's rules allow, and the optimum (evaluate.climb)."""
    from ftfof.evaluate.table import MOVED, NOT_CLIMBED, climbs_of
    from ftfof.pipeline.climb import run_table
    from ftfof.pipeline.params_file import load_params

    climbed = run_table(load_params(params_path), optimize, out, record, workers)
    for name, row in climbs_of(climbed).items():
        ended = f"FELL: {row['fall']}" if row["fell"] else "climbed"
        console.print(f"  {name:16s} {row['steps_done']} steps, {ended}")
    for name, why in climbed.get(NOT_CLIMBED, {}).items():
        console.print(f"  {name:16s} not climbed: {why}")
    if MOVED in climbed:
        console.print(f"  [yellow]{climbed[MOVED]['why']}")
    console.print(f"-> {record}")
