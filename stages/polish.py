"""Stage `polish`: NSGA-II on the simulator from the candidates refine's check passed.

The search is :mod:`ftfof.pipeline.polish`; its journal under ``data/polish/`` lets an
interrupted run resume, and ``data/polish/optimize`` is what `evaluate` reads.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, WorkersOption, console, stage

OPTIMIZE = path("refine_optimize")
MODELS = path("refine_models")
OUT = path("polish")
REPORT = path("polish_report")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    optimize: Annotated[Path, typer.Option(help="Optimum and front (refine's).")] = OPTIMIZE,
    models: Annotated[Path, typer.Option(help="The surrogates it was found on.")] = MODELS,
    out: Annotated[Path, typer.Option(help="Journal and the polished optimum.")] = OUT,
    report: Annotated[Path, typer.Option(help="What the polish did (JSON).")] = REPORT,
    workers: Annotated[int | None, WorkersOption] = None,
) -> None:
    """Search in simulation from the verified candidates; RHS on what the simulator measured."""
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.polish import Paths, run

    params = load_params(params_path)
    summary = run(params, Paths(optimize, models, out, report), workers)
    if summary["polished"]:
        change = ", ".join(
            f"{k} {v:+.1f} %" for k, v in summary["change_vs_start"].items() if v is not None
        )
        console.print(
            f"polish: {summary['simulated']} trajectories simulated ({summary['refused']} "
            f"refused) in {summary['seconds']:.0f} s; against refine's optimum: {change} -> {out}"
        )
