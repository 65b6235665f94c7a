"""Stage `dataset`: acquisitions (+ imported logs) -> data/dataset/ (Parquet) for the surrogates."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, stage

ACQUISITION = path("acquisition")
IMPORTED = path("imported")
OUT = path("dataset")
METRICS = path("dataset_metrics")
PLOT = path("dataset_figure")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    acquisition: Annotated[Path, typer.Option(help="Acquisition directory.")] = ACQUISITION,
    imported: Annotated[Path, typer.Option(help="Imported logs directory.")] = IMPORTED,
    out: Annotated[Path, typer.Option(help="Dataset directory to write.")] = OUT,
    metrics: Annotated[Path, typer.Option(help="Summary metrics JSON.")] = METRICS,
    plot: Annotated[Path, typer.Option(help="PNG of a few samples.")] = PLOT,
) -> None:
    """Resample every ok sample to fixed-length sequences, split 85/15, normalise on train."""
    from ftfof.files import save_figure
    from ftfof.pipeline.dataset import build
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.summaries import write_metrics
    from ftfof.surrogate.store import FILE, write_dataset

    built = build(load_params(params_path), acquisition, imported)
    # Everything is computed; now write: the dataset directory appears whole or not at all.
    write_dataset(out, built.table)
    write_metrics("dataset", metrics, built.summary)
    save_figure(built.figure, plot)
    s = built.summary
    console.print(
        f"dataset: {s['train']} train, {s['validation']} validation, "
        f"{s['baseline']} baselines ({s['excluded_failed']} failed samples left out) "
        f"-> {out / FILE}"
    )
