"""Stage `refine`: re-simulate the front, grow the dataset there, fine-tune, search again.

The loop is :mod:`ftfof.pipeline.refine`; each round's simulations are a resumable job under
``data/refine/round-<k>/``, and ``data/refine/{models,optimize}`` are what `evaluate` reads.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, WorkersOption, console, stage

DATASET = path("dataset")
ACQUISITION = path("acquisition")
MODELS = path("models")
OPTIMIZE = path("optimize")
OUT = path("refine")
REPORT = path("refine_report")
FIGURE = path("refine_figure")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    dataset: Annotated[Path, typer.Option(help="The dataset stage's directory.")] = DATASET,
    acquisition: Annotated[
        Path, typer.Option(help="The acquire stage's simulations (clean ones are nominees).")
    ] = ACQUISITION,
    models: Annotated[Path, typer.Option(help="The train stage's models.")] = MODELS,
    optimize: Annotated[Path, typer.Option(help="The optimize stage's directory.")] = OPTIMIZE,
    out: Annotated[Path, typer.Option(help="Rounds and final models, optimum, dataset.")] = OUT,
    report: Annotated[Path, typer.Option(help="Fidelity per round (JSON).")] = REPORT,
    figure: Annotated[Path, typer.Option(help="Fidelity against round (PNG).")] = FIGURE,
    workers: Annotated[int | None, WorkersOption] = None,
) -> None:
    """Simulate where the optimiser went, train there (warm start) and search again."""
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.refine import Paths, run

    params = load_params(params_path)
    paths = Paths(dataset, acquisition, models, optimize, out, report, figure)
    rounds = run(params, paths, workers)["rounds"]
    total = sum(r["seconds"] for r in rounds)
    console.print(
        f"refine: {len(rounds)} of {params.refine.rounds} rounds, "
        f"{sum(r['added'] for r in rounds)} samples added in {total:.0f} s -> {out}"
    )
