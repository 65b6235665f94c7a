"""`ftfof study eps`: the ε-Bezier baseline swept over ε on the platform (the ε-Bezier paper's
Fig. 15-16) -> reports/eps_study.json and reports/eps_study.png."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, stage

REPORT = path("eps_study")
FIGURE = path("eps_study_figure")

app = typer.Typer(
    help="Studies: the ε sweep on the platform (a stage), the payload margin on the robot.",
    no_args_is_help=True,
    add_completion=False,
)


@app.command("eps")
@stage
def eps(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    epsilons: Annotated[
        str | None,
        typer.Option(help="The ε values, comma-separated (0: plain Bezier; default study.eps)."),
    ] = None,
    workers: Annotated[int, typer.Option(min=0, help="Parallel simulations (0: all cores).")] = 0,
    report: Annotated[Path, typer.Option(help="Study report JSON.")] = REPORT,
    figure: Annotated[Path, typer.Option(help="Study figure PNG.")] = FIGURE,
) -> None:
    """Landing impact and body jitter of the ε-Bezier baseline at each ε."""
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.study import run
    from ftfof.study.eps import parse_epsilons

    params = load_params(params_path)
    values = params.study.eps if epsilons is None else parse_epsilons(epsilons)
    points = run(params, values, report, figure, workers)
    console.print("    ε   landing Fp (N)  dFp/dt (N/s)  body peak (m/s²)  detachment (m/s²)")
    for p in points:
        console.print(
            f"{p.eps:5g}  {p.landing_pre_pressure:14.2f}  {p.landing_rate:12.0f}  "
            f"{p.peak_body_acc:16.2f}  {p.detachment_jitter:17.2f}"
        )
    console.print(f"wrote {report} and {figure}")
