"""Stage `dataset`: acquisitions (+ imported logs) -> data/dataset/ (Parquet) for the surrogates."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from stages.common import ParamsOption, atomic_dir, atomic_path, console, stage, write_json

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
    import json

    import numpy as np
    import pyarrow as pa
    import pyarrow.parquet as pq

    from ftfof.data import dataset
    from ftfof.data.acquisition import ACQUISITION as SCHEMA
    from ftfof.report.figures import dataset_figure
    from stages.acquisition import versions
    from stages.common import read_table
    from stages.params import load_params

    params = load_params(params_path)
    tables = [read_table(acquisition / "samples.parquet", SCHEMA, "acquisition")]
    for path in sorted(imported.glob("*.parquet")) if imported.exists() else []:
        tables.append(read_table(path, SCHEMA, "imported log"))
    table = pa.concat_tables(tables)
    keys = table.column("key").to_pylist()
    if len(set(keys)) != len(keys):
        raise_duplicate(keys)
    built, norm = dataset.build(
        table, params.dataset, params.base.seed + params.dataset.split_seed_offset
    )
    manifest = acquisition / "manifest.json"
    sim_versions = json.loads(manifest.read_text()).get("versions", {}) if manifest.exists() else {}
    meta = {
        "params_hash": params_digest(params),
        "robot": params.robot,
        "surface": params.surface,
        "exudyn": sim_versions.get("exudyn", versions()["exudyn"]),
        "ftfof": versions()["ftfof"],
        "seq_len": params.dataset.seq_len,
        "hold": params.dataset.hold,
        "normalization": json.loads(norm.to_json()),
    }
    built = built.replace_schema_metadata({dataset.METADATA_KEY: json.dumps(meta, sort_keys=True)})
    splits = built.column("split").to_pylist()
    sources = built.column("source").to_pylist()
    failed = table.num_rows - built.num_rows
    summary = {
        "samples": built.num_rows,
        "excluded_failed": failed,
        "train": splits.count("train"),
        "validation": splits.count("validation"),
        "baseline": splits.count("baseline"),
        "imported": sources.count("imported"),
        "seq_len": params.dataset.seq_len,
        "peak_detachment_mean": float(np.nanmean(built.column("peak_detachment").to_numpy())),
        "normalization": meta["normalization"],
    }
    fig = dataset_figure(built, params.dataset.plot_samples, params.base.seed)
    # Everything is computed; now write: the dataset directory appears whole or not at all.
    with atomic_dir(out) as tmp:
        pq.write_table(built, tmp / FILE)
    write_json(metrics, summary)
    with atomic_path(plot) as tmp_png:
        fig.savefig(tmp_png, format="png", dpi=100)
    console.print(
        f"dataset: {summary['train']} train, {summary['validation']} validation, "
        f"{summary['baseline']} baselines ({failed} failed samples left out) -> {out / FILE}"
    )


def raise_duplicate(keys: list[str]) -> None:
    from collections import Counter

    from ftfof.errors import DataError

    dup = [k for k, c in Counter(keys).items() if c > 1]
    raise DataError("dataset", f"sample {dup[0]!r} appears twice (imported twice?)")


def params_digest(params) -> str:
    import hashlib
    import json

    return hashlib.sha256(json.dumps(params.model_dump(), sort_keys=True).encode()).hexdigest()[:16]
