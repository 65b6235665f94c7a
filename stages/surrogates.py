"""Reading the dataset for training, and the trained surrogates for optimisation (stage IO)."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from ftfof.data import dataset
from ftfof.errors import DataError
from ftfof.pipeline.digests import files_sha256
from ftfof.surrogate.predict import GRUWeights, Surrogate
from stages.common import read_table

FILE = "samples.parquet"


@dataclass
class TrainingData:
    table: pa.Table
    normalization: dataset.Normalization
    seq_len: int
    hold: float
    metadata_digest: str

    @cached_property
    def _arrays(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        mean = np.asarray(self.normalization.input_mean)
        scale = np.asarray(self.normalization.input_scale)
        out = {}
        for split in ("train", "validation", "baseline"):
            x, y = dataset.arrays(self.table, split)
            out[split] = (
                ((x - mean) / scale).astype(np.float32),
                (y / np.asarray(self.target_scale)).astype(np.float32),
            )
        return out

    @property
    def target_scale(self) -> list[float]:
        return self.normalization.target_scale

    @property
    def dt(self) -> float:
        t = np.asarray(self.table.column("t")[0].as_py())
        return float(t[1] - t[0])

    def inputs(self, split: str) -> np.ndarray:
        return self._arrays[split][0]

    def target(self, split: str, index: int) -> np.ndarray:
        return self._arrays[split][1][..., index : index + 1]


def read_dataset(directory: Path) -> TrainingData:
    path = directory / FILE
    if not path.exists():
        raise DataError(str(path), "dataset not found (run `ftfof dataset` first)")
    try:
        meta_raw = pq.read_schema(path).metadata or {}
    except (pa.ArrowException, OSError) as err:
        raise DataError(str(path), f"unreadable dataset ({str(err).splitlines()[0]})") from None
    if dataset.METADATA_KEY not in meta_raw:
        raise DataError(str(path), "not an ftfof dataset (no ftfof metadata)")
    meta = json.loads(meta_raw[dataset.METADATA_KEY])
    table = read_table(path, dataset.schema(meta["seq_len"]), "dataset")
    if not np.any(np.array(table.column("split").to_pylist()) == "train"):
        raise DataError(str(path), "has no training samples")
    norm = dataset.Normalization(**meta["normalization"])
    digest = hashlib.sha256(meta_raw[dataset.METADATA_KEY]).hexdigest()[:16]
    return TrainingData(table, norm, meta["seq_len"], meta["hold"], digest)


def load_surrogate(
    directory: Path, loss: str | None = None, weights: dict[str, Path] | None = None
) -> Surrogate:
    """The trained Fd and Fp models of one loss (default: the config's ``use``).

    ``weights`` replaces the state-dict files by target (the registry's copies, already checked
    against ``directory``); normalisation and model config always come from ``directory``.
    """
    import torch

    config_path = directory / "config.json"
    if not config_path.exists():
        raise DataError(str(directory), "no trained models (run `ftfof train` first)")
    config = json.loads(config_path.read_text())
    loss = loss or config["use"]
    models = []
    for target in ("Fd", "Fp"):
        path = (weights or {}).get(target) or directory / f"{target}_{loss}.pt"
        if not path.exists():
            raise DataError(str(path), f"missing model for {target} with the {loss} loss")
        state = torch.load(path, weights_only=True)
        models.append(GRUWeights.from_state({k: v.numpy() for k, v in state.items()}))
    norm = dataset.Normalization.from_json((directory / "normalization.json").read_text())
    return Surrogate(models[0], models[1], norm, config["seq_len"], config["hold"])


def models_digest(directory: Path) -> str:
    """SHA-256 (16 hex) of every file in the model directory: names a set of trained surrogates.

    The train stage tags its MLflow run with it, so a later stage can find the run that produced
    the models it used without storing a run id inside the (DVC-tracked) model directory.
    """
    if not directory.is_dir():
        raise DataError(str(directory), "no trained models (run `ftfof train` first)")
    return files_sha256(p for p in directory.iterdir() if p.is_file())
