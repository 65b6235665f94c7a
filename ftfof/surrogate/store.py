"""The surrogates on disk: the dataset as training arrays, and the model directory, whose format
is defined here once, by its writer and its reader side by side.

A model directory holds one state dict per loss (``torch.load(weights_only=True)``), each a
multi-output GRU over every target of :mod:`ftfof.data.targets`, ``normalization.json``,
``config.json`` (which targets the training data supplied) and, where asked for, ``peaks.json``
(the GPs of some targets' peaks, :mod:`ftfof.surrogate.peaks`); it is written whole or not at all.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from ftfof.config import Train
from ftfof.data import dataset, refinement
from ftfof.digests import bytes_sha256
from ftfof.errors import DataError
from ftfof.files import atomic_dir, read_table
from ftfof.surrogate.peaks import PeakPredictor, peak_model_from_dict
from ftfof.surrogate.predict import GRUWeights, Surrogate
from ftfof.trajectory.bezier import DECISION_NAMES

FILE = "samples.parquet"
PEAKS = "peaks.json"
TARGETS = dataset.TARGETS


def weights_file(loss: str) -> str:
    """The state-dict file of one model, in the model directory and in the registry alike."""
    return f"surrogate_{loss}.pt"


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
                self.normalization.to_model(y).astype(np.float32),
            )
        return out

    @property
    def trained(self) -> tuple[str, ...]:
        """The targets some training sample supplies (the others are masked out everywhere)."""
        y = self._arrays["train"][1]
        return tuple(n for k, n in enumerate(TARGETS) if np.isfinite(y[..., k]).any())

    @property
    def dt(self) -> float:
        t = np.asarray(self.table.column("t")[0].as_py())
        return float(t[1] - t[0])

    def inputs(self, split: str) -> np.ndarray:
        return self._arrays[split][0]

    def targets(self, split: str) -> np.ndarray:
        """(n, N, K) targets as the model fits them (tamed, scaled), NaN where a sample does not
        supply one."""
        return self._arrays[split][1]

    def decisions(self, split: str) -> np.ndarray:
        """(n, 12) control values of the split's samples (NaN for a log, which has none)."""
        rows = np.asarray(self.table.column("split").to_pylist()) == split
        return np.column_stack(
            [self.table.column(n).to_numpy()[rows] for n in DECISION_NAMES]
        ).astype(float)

    def from_rounds(self, split: str) -> np.ndarray:
        """(n,) whether each of the split's samples is a refinement round's (near the front)."""
        rows = np.asarray(self.table.column("split").to_pylist()) == split
        sources = np.asarray(self.table.column("source").to_pylist())[rows]
        return np.asarray(refinement.from_rounds(sources.tolist()), dtype=bool)

    def peaks(self, split: str, target: str) -> np.ndarray:
        """(n,) the maximum of one target's series, in its unit (NaN where not supplied)."""
        k = TARGETS.index(target)  # the tail's map is monotone: it maps the maximum
        return self.normalization.target_from_model(np.max(self.targets(split)[..., k], axis=-1), k)


def write_dataset(directory: Path, table: pa.Table) -> None:
    """The dataset ``table`` (its ftfof metadata in the schema) as ``directory``, whole or not at
    all."""
    with atomic_dir(directory) as tmp:
        pq.write_table(table, tmp / FILE)


def read_dataset(directory: Path) -> TrainingData:
    """The dataset ``directory``, checked to be one: any problem is one DataError."""
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
    digest = bytes_sha256(meta_raw[dataset.METADATA_KEY], 16)
    return TrainingData(table, norm, meta["seq_len"], meta["hold"], digest)


def write_models(
    out: Path,
    results: list[dict[str, Any]],
    data: TrainingData,
    cfg: Train,
    peaks: dict[str, PeakPredictor],
) -> None:
    """State dicts of the trained ``results``, normalisation, peak models and config, all or
    nothing."""
    import torch

    with atomic_dir(out) as tmp:
        if peaks:
            text = json.dumps({n: m.as_dict() for n, m in sorted(peaks.items())})
            (tmp / PEAKS).write_text(text + "\n")
        for r in results:
            state = {k: torch.from_numpy(v) for k, v in r["state"].items()}
            torch.save(state, tmp / weights_file(r["kind"]))
        (tmp / "normalization.json").write_text(data.normalization.to_json() + "\n")
        config = {
            "model": {
                "inputs": 4,
                "hidden": cfg.hidden,
                "layers": cfg.layers,
                "dropout": cfg.dropout,
                "outputs": len(TARGETS),
            },
            "targets": list(TARGETS),
            "trained": list(data.trained),
            "losses": list(cfg.losses),
            "use": cfg.use,
            "peaks": sorted(peaks),
            "seq_len": data.seq_len,
            "hold": data.hold,
            "dataset": data.metadata_digest,
        }
        (tmp / "config.json").write_text(json.dumps(config, indent=2, sort_keys=True) + "\n")


def load_states(directory: Path) -> dict[str, dict[str, np.ndarray]]:
    """Every model's state dict in ``directory`` as NumPy arrays, by loss: what a fine-tuning
    starts from."""
    import torch

    config_path = directory / "config.json"
    if not config_path.exists():
        raise DataError(str(directory), "no trained models (run `ftfof train` first)")
    config = json.loads(config_path.read_text())
    out = {}
    for loss in config["losses"]:
        path = directory / weights_file(loss)
        if not path.exists():
            raise DataError(str(path), f"missing model for the {loss} loss")
        state = torch.load(path, weights_only=True)
        out[loss] = {k: v.numpy() for k, v in state.items()}
    return out


def load_surrogate(
    directory: Path, loss: str | None = None, weights: Path | None = None
) -> Surrogate:
    """The trained model of one loss (default: the config's ``use``).

    ``weights`` replaces the state-dict file (the registry's copy, already checked against
    ``directory``); normalisation and model config always come from ``directory``.
    """
    import torch

    config_path = directory / "config.json"
    if not config_path.exists():
        raise DataError(str(directory), "no trained models (run `ftfof train` first)")
    config = json.loads(config_path.read_text())
    loss = loss or config["use"]
    path = weights or directory / weights_file(loss)
    if not path.exists():
        raise DataError(str(path), f"missing model for the {loss} loss")
    state = torch.load(path, weights_only=True)
    model = GRUWeights.from_state({k: v.numpy() for k, v in state.items()})
    norm = dataset.Normalization.from_json((directory / "normalization.json").read_text())
    return Surrogate(
        model,
        tuple(config["targets"]),
        tuple(config["trained"]),
        norm,
        config["seq_len"],
        config["hold"],
        _load_peaks(directory, config),
    )


def _load_peaks(directory: Path, config: dict[str, Any]) -> dict[str, PeakPredictor]:
    """The peak models ``config.json`` lists (none for models trained without them)."""
    names = config.get("peaks", [])
    if not names:
        return {}
    path = directory / PEAKS
    if not path.exists():
        raise DataError(str(path), f"missing: config.json lists peak models of {names}")
    saved = json.loads(path.read_text())
    if sorted(saved) != sorted(names):
        raise DataError(str(path), f"holds peak models of {sorted(saved)}, config lists {names}")
    return {n: peak_model_from_dict(saved[n]) for n in names}
