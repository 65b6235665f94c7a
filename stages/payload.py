"""`ftfof study payload`: the largest mass added to the trunk at which each Table I trajectory
and the optimum still climb every step (bisection) -> reports/payload.json and .png. A command,
not a pipeline stage: it climbs each trajectory about eight times."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, stage

OPTIMIZE = path("polish_optimize")
REPORT = path("payload")
FIGURE = path("payload_figure")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    optimize: Annotated[Path, typer.Option(help="The optimum and its front.")] = OPTIMIZE,
    workers: Annotated[int, typer.Option(min=0, help="Parallel climbs (0: all cores).")] = 0,
    report: Annotated[Path, typer.Option(help="Study report JSON.")] = REPORT,
    figure: Annotated[Path, typer.Option(help="Study figure PNG.")] = FIGURE,
) -> None:
    """Each trajectory's payload margin: the heaviest added trunk mass it climbs every step with
    (study.payload: ceiling and resolution)."""
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.payload import run

    out = run(load_params(params_path), optimize, report, figure, workers)
    console.print(f"payload margin of {out['robot']} on {out['surface']} (+ kg on the trunk):")
    for name, m in out["margins"].items():
        upper = "the ceiling" if m["fell_with"] is None else f"fell with {m['fell_with']:g}"
        margin = f"{m['payload']:g} kg ({upper})" if m["climbs_unloaded"] else "falls unloaded"
        console.print(f"  {name:16s} {margin}")
    console.print(f"wrote {report} and {figure}")
