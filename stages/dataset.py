"""Stage `dataset`: acquisitions (+ imported logs) -> data/dataset/ (Parquet) for the surrogates."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from stages.common import ParamsOption, console, stage

ACQUISITION = Path("data/acquisition")
IMPORTED = Path("data/imported")
OUT = Path("data/dataset")
METRICS = Path("reports/dataset.json")
PLOT = Path("reports/dataset_samples.png")
FILE = "samples.parquet"


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
    import pyarrow.parquet as pq

    from ftfof.files import atomic_dir, save_figure, write_json
    from ftfof.pipeline.dataset import build
    from ftfof.pipeline.params_file import load_params

    built = build(load_params(params_path), acquisition, imported)
    # Everything is computed; now write: the dataset directory appears whole or not at all.
    with atomic_dir(out) as tmp:
        pq.write_table(built.table, tmp / FILE)
    write_json(metrics, built.summary)
    save_figure(built.figure, plot)
    s = built.summary
    console.print(
        f"dataset: {s['train']} train, {s['validation']} validation, "
        f"{s['baseline']} baselines ({s['excluded_failed']} failed samples left out) "
        f"-> {out / FILE}"
    )
