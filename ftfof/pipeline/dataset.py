"""The `dataset` run: acquisitions and imported logs -> one table of fixed-length sequences with
the metadata (params digest, code versions, normalisation) that the surrogates are trained on."""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pyarrow as pa

from ftfof.config import Params
from ftfof.data import dataset
from ftfof.data.acquisition import ACQUISITION
from ftfof.files import read_table
from ftfof.pipeline.jobs import FINAL, MANIFEST, versions
from ftfof.seeds import seed_for


@dataclass
class Dataset:
    table: pa.Table  # with the ftfof metadata
    summary: dict[str, Any]  # the stage's metrics
    figure: Any  # a few samples (matplotlib)


def build(params: Params, acquisition: Path, imported: Path) -> Dataset:
    """Resample every ok sample, split and normalise on train; a duplicate key is an error."""
    from ftfof.report.figures import dataset_figure

    started = time.perf_counter()
    tables = [read_table(acquisition / FINAL, ACQUISITION, "acquisition")]
    for path in sorted(imported.glob("*.parquet")) if imported.exists() else []:
        tables.append(read_table(path, ACQUISITION, "imported log"))
    cfg = params.dataset
    manifest = acquisition / MANIFEST
    sim_versions = json.loads(manifest.read_text()).get("versions", {}) if manifest.exists() else {}
    built = dataset.built_from(params.base.seed, params.robot, params.selected_robot.timing, cfg)
    provenance = dataset.provenance(built, params.surface, sim_versions, versions())
    seed, landing_start = seed_for(params.base.seed, "split"), params.selected_robot.timing.T2
    built, summary = dataset.assemble(tables, cfg, seed, landing_start, provenance)
    # the stage's time (not hashed)
    summary = {"seconds": round(time.perf_counter() - started, 2), **summary}
    return Dataset(
        built, summary, dataset_figure(built, cfg.plot_samples, seed_for(params.base.seed, "plots"))
    )
