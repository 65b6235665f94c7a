"""Acquisitions -> fixed-length training sequences for the surrogates (FTFOF §IV.B).

One row per sample with fixed-length list columns. Each sample is cut to its trajectory time
base [0, T3 + hold] and resampled to ``seq_len`` bins: the commanded foot x, z at the bin centres
and their velocities (differentiated from the commanded positions at the acquisition rate), and
the targets of :mod:`ftfof.data.targets` (each on its window, binned so that the objectives read
the same values from them as from the full-rate record; NaN where a record cannot supply one).
Baselines stay in the table with split ``baseline`` and out of training; the rest is split 85/15
by sample with a seeded permutation. Normalisation statistics come from the training split only.
"""

from __future__ import annotations

import json
import warnings
from collections import Counter
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pyarrow as pa
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.data import tails
from ftfof.data import targets as tg
from ftfof.data.schema import field
from ftfof.digests import json_sha256
from ftfof.errors import DataError
from ftfof.trajectory.bezier import DECISION_NAMES

Array = NDArray[np.float64]
INPUTS = ("x", "z", "vx", "vz")
TARGETS = tg.TARGETS
UNITS = {
    "x": "m",
    "z": "m",
    "vx": "m/s",
    "vz": "m/s",
    "t": "s",
    "film_curvature": "1/m",
    "film_clearance": "m",
    **tg.UNITS,
}
# the film channels are NaN where a record does not see the film (a force log): their targets
# are masked
CHANNELS = (
    "t",
    "x_cmd",
    "z_cmd",
    "Fx_pad",
    "Fz_pad",
    "body_acc",
    "bonds",
    "switch",
    "film_curvature",
    "film_clearance",
)
METADATA_KEY = b"ftfof"


def built_from(seed: int, robot: str, timing: config.Timing, cfg: config.Dataset) -> dict[str, Any]:
    """The params a dataset is built from (dvc.yaml's ``dataset`` params), which its metadata
    hashes: a hash of all of them rewrote the dataset, and every digest downstream, on an edit
    of a later stage's settings (the polish budget, the report)."""
    return {
        "seed": seed,
        "robot": robot,
        "timing": timing.model_dump(),
        "dataset": cfg.model_dump(),
    }


def provenance(
    built: dict[str, Any], surface: str, simulated: dict[str, str], versions: dict[str, str]
) -> dict[str, Any]:
    """The dataset's provenance (:func:`built_from`'s hash, the robot and surface, the code):
    exudyn as the acquisition's ``simulated`` versions name it, where they do, else this one."""
    return {
        "params_hash": json_sha256(built, 16),
        "robot": built["robot"],
        "surface": surface,
        "exudyn": simulated.get("exudyn", versions["exudyn"]),
        "ftfof": versions["ftfof"],
    }


def schema(seq_len: int) -> pa.Schema:
    seq = pa.list_(pa.float32(), seq_len)
    series = [
        field(n, seq, UNITS[n], f"{n} on the trajectory time base")
        for n in ("t", *INPUTS, *TARGETS)
    ]
    return pa.schema(
        [
            field("key", pa.string(), "", "source:sample_id"),
            field("source", pa.string(), "", "sampled | baseline:<name> | imported"),
            field("sample_id", pa.int64(), "", "row of the trajectory table (sampled)"),
            field("split", pa.string(), "", "train | validation | baseline"),
            *[
                field(n, pa.float64(), "m", f"control point {n} (NaN if not a Bezier)")
                for n in DECISION_NAMES
            ],
            field("T3", pa.float64(), "s", "trajectory duration"),
            field("peak_detachment", pa.float64(), "N", "max Fd of the full-rate series"),
            field("peak_pre_pressure", pa.float64(), "N", "max Fp of the full-rate series"),
            field("peak_body_acc", pa.float64(), "m/s^2", "max body jitter"),
            *series,
        ]
    )


@dataclass(frozen=True)
class Normalization:
    """Per-feature affine scaling fitted on the training split: (value - mean) / scale; each
    target's heavy tail tamed first (:mod:`ftfof.data.tails`), by ``target_tails``' (fence,
    spread) per target (None: an older dataset, no taming)."""

    input_mean: list[float]
    input_scale: list[float]
    target_scale: list[float]  # targets are only scaled (they are >= 0 and 0 off their windows)
    target_tails: list[list[float]] | None = None

    @classmethod
    def fit(cls, inputs: Array, targets: Array, tail_fence: float = 0.0) -> Normalization:
        """``inputs`` (n, seq, 4), ``targets`` (n, seq, K) of the training split (NaN = missing);
        each target's scale is its RMS over the samples that supply it, its tail fence
        ``tail_fence`` IQRs above the upper quartile of their peaks (0: no taming)."""
        mean = inputs.mean(axis=(0, 1))
        scale = inputs.std(axis=(0, 1))
        with warnings.catch_warnings():  # a target no training sample supplies: all NaN
            warnings.simplefilter("ignore", RuntimeWarning)
            tscale = np.sqrt(np.nanmean(targets**2, axis=(0, 1)))
            peaks = np.nanmax(targets, axis=1)
        return cls(
            mean.tolist(),
            np.where(scale > 0, scale, 1.0).tolist(),
            np.where(tscale > 0, tscale, 1.0).tolist(),
            [list(tails.fence(peaks[:, k], tail_fence)) for k in range(targets.shape[-1])],
        )

    def tail(self, k: int) -> tuple[float, float]:
        """Target ``k``'s (fence, spread); (0, 0) leaves it as it is."""
        if self.target_tails is None:
            return 0.0, 0.0
        upper, spread = self.target_tails[k]
        return float(upper), float(spread)

    def to_model(self, targets: Array) -> Array:
        """(..., K) targets in their units -> what the model fits: tamed, then scaled."""
        return self._each(targets, tails.tame) / np.asarray(self.target_scale)

    def from_model(self, y: Array) -> Array:
        """The inverse of :meth:`to_model`: (..., K) model outputs -> targets in their units."""
        return self._each(np.asarray(y, dtype=float) * np.asarray(self.target_scale), tails.untame)

    def target_from_model(self, y: Array, k: int) -> Array:
        """Target ``k`` alone of :meth:`from_model`: ``y`` its model outputs, any shape."""
        return tails.untame(np.asarray(y, dtype=float) * self.target_scale[k], *self.tail(k))

    def _each(self, values: Array, mapping: Callable[[Array, float, float], Array]) -> Array:
        """``values`` (..., K) with each target's tail ``mapping`` applied (a target without a
        tail, spread 0, is copied as it is), in a new array."""
        out = np.array(values, dtype=float)
        for k in range(out.shape[-1]):
            out[..., k] = mapping(out[..., k], *self.tail(k))
        return out

    def to_json(self) -> str:
        return json.dumps(asdict(self))

    @classmethod
    def from_json(cls, text: str) -> Normalization:
        return cls(**json.loads(text))


def resample(
    channels: dict[str, Array],
    T3: float,
    hold: float,
    seq_len: int,
    landing_start: float | None = None,
    proof_held: float = np.nan,
) -> dict[str, Array]:
    """One sample's sequences; ``channels["t"]`` is time from the trajectory start,
    ``landing_start`` the robot's T2 (without it the ``retouch`` target is not supplied),
    ``proof_held`` its proof pull's verdict (NaN: a record without one, no ``holds`` target)."""
    t, x, z = channels["t"], channels["x_cmd"], channels["z_cmd"]
    grid = tg.time_base(T3, hold, seq_len)
    vx, vz = np.gradient(x, t), np.gradient(z, t)
    return {
        "t": grid,
        "x": np.interp(grid, t, x),
        "z": np.interp(grid, t, z),
        "vx": np.interp(grid, t, vx),
        "vz": np.interp(grid, t, vz),
        **tg.binned(channels, T3, hold, seq_len, landing_start, proof_held),
    }


def split(keys: list[str], fraction: float, seed: int) -> list[str]:
    """'train' / 'validation' per key: a seeded permutation, round(fraction * n) validation."""
    order = np.random.default_rng(seed).permutation(len(keys))
    n_val = round(fraction * len(keys))
    labels = np.full(len(keys), "train", dtype=object)
    labels[order[:n_val]] = "validation"
    return labels.tolist()


def build(
    acquisition: pa.Table,
    settings: config.Dataset,
    seed: int,
    landing_start: float | None = None,
) -> tuple[pa.Table, Normalization]:
    """The dataset table (ok samples only) and its training-split normalisation; ``landing_start``
    is the robot's T2 (the ``retouch`` target's window ends there)."""
    ok = acquisition.filter(pa.compute.equal(acquisition.column("status"), "ok"))
    if ok.num_rows == 0:
        raise DataError("dataset", "no successful samples in the acquisition")
    scalar_names = [
        "key",
        "source",
        "sample_id",
        *DECISION_NAMES,
        "T3",
        "peak_detachment",
        "peak_pre_pressure",
        "peak_body_acc",
    ]
    cols = ok.select(scalar_names).to_pydict()
    seqs = _sequences(ok, cols["key"], cols["T3"], settings, landing_start)
    sources = cols["source"]
    labels = _labels(cols["key"], sources, settings.validation_fraction, seed)
    train = np.array([lab == "train" for lab in labels])
    if not train.any():
        raise DataError("dataset", "no training samples (only baselines?)")
    inputs = np.stack([seqs[k] for k in INPUTS], axis=-1)
    targets = np.stack([seqs[k] for k in TARGETS], axis=-1)
    norm = Normalization.fit(inputs[train], targets[train], settings.tail_fence)
    data = {
        "key": cols["key"],
        "source": sources,
        "sample_id": cols["sample_id"],
        "split": labels,
        **{k: cols[k] for k in DECISION_NAMES},
        "T3": cols["T3"],
        "peak_detachment": cols["peak_detachment"],
        "peak_pre_pressure": cols["peak_pre_pressure"],
        "peak_body_acc": cols["peak_body_acc"],
        **{k: list(v.astype(np.float32)) for k, v in seqs.items()},
    }
    return pa.Table.from_pydict(data, schema=schema(settings.seq_len)), norm


def _sequences(
    ok: pa.Table,
    keys: list[str],
    T3: list[float],
    settings: config.Dataset,
    landing_start: float | None,
) -> dict[str, Array]:
    """Every sample's resampled sequences (:func:`resample`), stacked by name (n, seq_len); a
    sample whose time does not strictly increase is refused by key."""
    series = {c: list_column(ok, c) for c in CHANNELS}
    n = ok.num_rows
    # a table from before the proof pull, or an imported log without the phase: no verdict
    held = (
        ok.column("proof_held").to_numpy()
        if "proof_held" in ok.column_names
        else np.full(n, np.nan)
    )
    seqs = {name: np.empty((n, settings.seq_len)) for name in ("t", *INPUTS, *TARGETS)}
    for i in range(n):  # once per dataset build, not a hot path
        t = series["t"][i]
        if t.size < 2 or np.any(np.diff(t) <= 0):
            raise DataError(keys[i], "series time is not strictly increasing")
        channels = {c: series[c][i] for c in CHANNELS}
        s = resample(channels, T3[i], settings.hold, settings.seq_len, landing_start, held[i])
        for name, values in s.items():
            seqs[name][i] = values
    return seqs


def _labels(keys: list[str], sources: list[str], fraction: float, seed: int) -> list[str]:
    """Each sample's split: baselines stay ``baseline``, the rest are :func:`split`."""
    trainable = [i for i, src in enumerate(sources) if not src.startswith("baseline:")]
    labels = ["baseline"] * len(keys)
    for i, lab in zip(trainable, split([keys[i] for i in trainable], fraction, seed), strict=True):
        labels[i] = lab
    return labels


def assemble(
    tables: list[pa.Table],
    settings: config.Dataset,
    seed: int,
    landing_start: float,
    provenance: dict[str, Any],
) -> tuple[pa.Table, dict[str, Any]]:
    """The dataset of the acquired and imported ``tables`` (:func:`build`; a sample in two is an
    error), its metadata ``provenance`` with the sequence settings and the normalisation, and
    its summary (:func:`summarize`, and the normalisation)."""
    table = pa.concat_tables(tables)
    keys = table.column("key").to_pylist()
    if dup := [k for k, c in Counter(keys).items() if c > 1]:
        raise DataError("dataset", f"sample {dup[0]!r} appears twice (imported twice?)")
    built, norm = build(table, settings, seed, landing_start)
    meta = {
        **provenance,
        "seq_len": settings.seq_len,
        "hold": settings.hold,
        "normalization": json.loads(norm.to_json()),
    }
    built = built.replace_schema_metadata({METADATA_KEY: json.dumps(meta, sort_keys=True)})
    summary = {
        **summarize(built, table.num_rows, settings.seq_len),
        "normalization": meta["normalization"],
    }
    return built, summary


def list_column(table: pa.Table, name: str) -> list[Array]:
    """A list<float> column as float64 arrays, sliced from the Arrow buffers (no Python floats)."""
    col = table.column(name).combine_chunks()
    values = col.values.to_numpy(zero_copy_only=False).astype(np.float64)
    offsets = col.offsets.to_numpy()
    return [values[offsets[i] : offsets[i + 1]] for i in range(len(col))]


def arrays(table: pa.Table, split_name: str) -> tuple[Array, Array]:
    """(inputs (n, seq, 4), targets (n, seq, K), NaN = not supplied) of one split, float32."""
    rows = table.filter(pa.compute.equal(table.column("split"), split_name))

    def stack(names: tuple[str, ...]) -> Array:
        if rows.num_rows == 0:  # e.g. no baselines acquired: an empty split, not an error
            return np.empty((0, len(table.column("t")[0]) if table.num_rows else 0, len(names)))
        return np.stack(
            [np.stack(rows.column(k).to_numpy(zero_copy_only=False)) for k in names], axis=-1
        )

    return stack(INPUTS).astype(np.float32), stack(TARGETS).astype(np.float32)


def summarize(built: pa.Table, acquired: int, seq_len: int) -> dict[str, Any]:
    """A built dataset in numbers: its splits, the ``acquired`` samples it left out (failed),
    the imported logs and how many of them carry the proof pull, how many samples supply each
    target (the rest are masked) and the mean peak detachment."""
    splits = built.column("split").to_pylist()
    imported = np.array(built.column("source").to_pylist()) == "imported"
    holds = built.column("holds").to_numpy(zero_copy_only=False)
    return {
        "samples": built.num_rows,
        "excluded_failed": acquired - built.num_rows,
        "train": splits.count("train"),
        "validation": splits.count("validation"),
        "baseline": splits.count("baseline"),
        "imported": int(imported.sum()),
        # imported logs that carry the platform's proof pull (the rest supply no `holds` target)
        "imported_with_proof": int(
            sum(np.isfinite(holds[i]).all() for i in np.flatnonzero(imported))
        ),
        "seq_len": seq_len,
        "targets_supplied": {
            name: int(
                sum(np.isfinite(v).all() for v in built.column(name).to_numpy(zero_copy_only=False))
            )
            for name in TARGETS
        },
        "peak_detachment_mean": float(np.nanmean(built.column("peak_detachment").to_numpy())),
    }
