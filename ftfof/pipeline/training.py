"""The `train` run: one multi-output GRU per loss, side by side in processes, the GPs of the
peaks ``train.peaks`` names, and its MLflow runs (a parent per invocation, a child per model,
every model registered as a version)."""

from __future__ import annotations

import multiprocessing
import os
import time
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ftfof.config import Params, Train
from ftfof.digests import models_digest
from ftfof.errors import DataError
from ftfof.pipeline import tracking
from ftfof.pipeline.registry import model_name, weights_tags
from ftfof.seeds import seed_for
from ftfof.stats import rank_rho
from ftfof.surrogate.peaks import (
    NearFront,
    PeakModel,
    PeakPredictor,
    fit_peak_model,
    near_front,
)
from ftfof.surrogate.store import PEAKS, TARGETS, TrainingData, weights_file
from ftfof.trajectory.bezier import DECISION_NAMES

MIN_PEAK_ROWS = 3  # training rows with control values and the target a peak GP needs
# the refinement rounds' training rows a local GP near the front needs: its 14 hyperparameters
# are fitted on them (a paper-scale round adds ~43)
MIN_NEAR_FRONT_ROWS = 20


@dataclass
class Training:
    results: list[dict[str, Any]]  # one per loss: job, state dict, history, metrics, predictions
    peaks: dict[str, PeakPredictor]  # target -> the GP of its peak
    summary: dict[str, Any]  # the stage's metrics
    wall: float  # seconds


def train_all(
    params: Params,
    data: TrainingData,
    *,
    warm_start: Mapping[str, dict[str, np.ndarray]] | None = None,
    peaks_from: Mapping[str, PeakPredictor] | None = None,
    near_front_peaks: Sequence[str] = (),
) -> Training:
    """Train the multi-output model with every loss, on the same split and seed, then the peak
    models.

    ``warm_start`` maps each loss to the state dict its model fine-tunes from (every loss must be
    there); without it every model starts from its seeded initialisation. ``peaks_from``: peak
    models refitted on ``data`` with their hyperparameters (fine-tuning) instead of fitted anew;
    the ``near_front_peaks`` targets also get a local GP on the refinement rounds' rows
    (:class:`ftfof.surrogate.peaks.NearFront`) once they have :data:`MIN_NEAR_FRONT_ROWS`,
    blended with their broad GP or, without one, with the GRU's maximum.
    """
    cfg = params.train
    jobs = [{"kind": k, "seed": seed_for(params.search_seed, "train", 0)} for k in cfg.losses]
    if warm_start is not None:
        for job in jobs:
            if job["kind"] not in warm_start:
                raise DataError("warm start", f"no weights for the {job['kind']} loss")
            job["warm_start"] = warm_start[job["kind"]]
    started = time.perf_counter()
    previous = dict(peaks_from or {})
    if cfg.parallel and cfg.peaks and not previous:
        # each fit in a process of its own beside the GRUs (one core each: a GRU this size
        # gains nothing from a second thread): at paper scale the two fits took 38 s one after
        # the other, the GRU 20 s; a refit is a solve
        targets = list(dict.fromkeys([*cfg.peaks, *near_front_peaks]))
        context = multiprocessing.get_context("fork")
        with ProcessPoolExecutor(len(targets), mp_context=context) as pool:
            fits = []
            for name in targets:
                named, near = _only(name, cfg.peaks, near_front_peaks)
                fits.append(pool.submit(fit_peaks, data, named, previous, near))
            results = run_jobs(jobs, data, cfg)
            peaks = {n: m for fit in fits for n, m in fit.result().items()}
    else:
        results = run_jobs(jobs, data, cfg)
        peaks = fit_peaks(data, cfg.peaks, previous, near_front_peaks)
    wall = time.perf_counter() - started
    summary: dict[str, Any] = {
        r["kind"]: {
            "epochs": len(r["history"]["train"]),
            "epoch_cap": cfg.epochs,
            "best_epoch": r["history"]["best_epoch"],
            "stopped_early": len(r["history"]["train"]) < cfg.epochs,
            "seconds": round(r["seconds"], 2),
            "targets": r["metrics"],
        }
        for r in results
    }
    summary["trained_targets"] = list(data.trained)
    use = next(r for r in results if r["kind"] == cfg.use)
    summary["peaks"] = {n: peak_metrics(m, data, use) for n, m in peaks.items()}
    summary["peaks_not_fitted"] = [n for n in cfg.peaks if n not in peaks]
    summary["wall_seconds"] = round(wall, 2)
    return Training(results, peaks, summary, wall)


def fit_peaks(
    data: TrainingData,
    names: list[str],
    previous: Mapping[str, PeakPredictor],
    near_front_peaks: Sequence[str] = (),
) -> dict[str, PeakPredictor]:
    """The GP of each named target's peak on the training split's control values (the rows that
    have both); refitted from ``previous`` where it has the target, with a local GP on the
    refinement rounds' rows for the ``near_front_peaks`` (once there are
    :data:`MIN_NEAR_FRONT_ROWS` of them); a near-front target that is not named gets the local
    GP alone, blended with its series model's maximum. A target with fewer than
    :data:`MIN_PEAK_ROWS` such rows (a dataset of imported logs, which have no control values)
    gets none: its peak stays the GRU's series maximum, and the summary says so."""
    from threadpoolctl import threadpool_limits

    # one BLAS thread: a multi-threaded Cholesky sums in another order on another core count,
    # and a refit that differs in its last bits sent refinement's search elsewhere
    with threadpool_limits(limits=1):
        return _fit_peaks(data, names, previous, near_front_peaks)


def _fit_peaks(
    data: TrainingData,
    names: list[str],
    previous: Mapping[str, PeakPredictor],
    near_front_peaks: Sequence[str],
) -> dict[str, PeakPredictor]:
    X = data.decisions("train")
    near = data.from_rounds("train")
    out: dict[str, PeakPredictor] = {}
    for name in dict.fromkeys([*names, *near_front_peaks]):
        y = data.peaks("train", name) if name in data.trained else np.full(len(X), np.nan)
        rows = np.isfinite(y) & np.isfinite(X).all(axis=1)
        if rows.sum() < MIN_PEAK_ROWS:
            continue
        broad = _broad(name, names, previous, X[rows], y[rows])
        local = rows & near
        if name in near_front_peaks and local.sum() >= MIN_NEAR_FRONT_ROWS:
            out[name] = near_front(name, broad, X[local], y[local])
        elif broad is not None:
            out[name] = broad
    return out


def _only(
    name: str, names: Sequence[str], near_front_peaks: Sequence[str]
) -> tuple[list[str], list[str]]:
    """:func:`fit_peaks`'s ``names`` and ``near_front_peaks`` for ``name`` alone."""
    return [name] if name in names else [], [name] if name in near_front_peaks else []


def _broad(
    name: str, names: list[str], previous: Mapping[str, PeakPredictor], X: np.ndarray, y: np.ndarray
) -> PeakModel | None:
    """The GP of ``name``'s peak over the whole design: refitted with the hyperparameters it has,
    fitted anew if it has none, None if it is not one of ``names`` (its series model's maximum
    stands in for it)."""
    if name not in names:
        return None
    before = previous.get(name)
    if isinstance(before, NearFront):
        before = before.broad
    return fit_peak_model(name, X, y) if before is None else before.refit(X, y)


def peak_metrics(model: PeakPredictor, data: TrainingData, use: dict[str, Any]) -> dict[str, Any]:
    """A peak model's validation errors beside the ``use`` GRU's series maximum, and what it
    learnt: the length scale of each control value (in standard deviations; small = matters)."""
    k = TARGETS.index(model.target)
    truth = data.peaks("validation", model.target)
    X = data.decisions("validation")
    rows = np.isfinite(truth) & np.isfinite(X).all(axis=1)
    gru = use["val_pred"][..., k].max(axis=-1)

    def errors(pred: np.ndarray) -> dict[str, float]:
        e = np.abs(pred[rows] - truth[rows])
        return {
            "n": int(rows.sum()),
            "peak_error_median": float(np.median(e)) if e.size else np.nan,
            "peak_error_p90": float(np.percentile(e, 90)) if e.size else np.nan,
            "spearman": rank_rho(pred[rows], truth[rows]),
        }

    return {
        "gp": errors(model(np.nan_to_num(X), gru)),
        "gru": errors(gru),
        "length_scales": dict(zip(DECISION_NAMES, model.length_scale.tolist(), strict=True)),
    }


def run_jobs(jobs: list[dict], data: TrainingData, cfg: Train) -> list[dict]:
    """Train every job, side by side in processes when asked (one torch thread pool each)."""
    cores = os.cpu_count() or 1
    workers = min(len(jobs), cores) if cfg.parallel else 1
    threads = cfg.threads or max(1, cores // workers)
    if workers == 1:
        return [_train_one(job, data, cfg, threads) for job in jobs]
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
        futures = [pool.submit(_train_one, job, data, cfg, threads) for job in jobs]
        return [f.result() for f in futures]


def _train_one(job: dict, data: TrainingData, cfg: Train, threads: int) -> dict:
    import numba
    import numpy as np
    import torch

    from ftfof.surrogate.train import predict, train_model, validation_metrics

    torch.set_num_threads(threads)
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    x_tr, y_tr = data.inputs("train"), data.targets("train")
    x_va, y_va = data.inputs("validation"), data.targets("validation")
    trained = train_model(
        x_tr,
        y_tr,
        x_va,
        y_va,
        job["kind"],
        cfg,
        job["seed"],
        TARGETS,
        warm_start=job.get("warm_start"),
    )
    scale = np.asarray(data.target_scale)
    pred = predict(trained.model, x_va) * scale
    truth = y_va * scale
    return {
        **{k: v for k, v in job.items() if k != "warm_start"},
        "state": {k: v.numpy() for k, v in trained.model.state_dict().items()},
        "history": {
            "train": trained.history.train,
            "validation": trained.history.validation,
            "best_epoch": trained.history.best_epoch,
        },
        "metrics": {
            name: validation_metrics(pred[..., k], truth[..., k], data.dt)
            for k, name in enumerate(TARGETS)
            if name in data.trained
        },
        "seconds": trained.seconds,
        "val_pred": pred,
        "val_truth": truth,
    }


def track(
    params: Params,
    run: Training,
    data: TrainingData,
    figures: tuple[Path, ...],
    out: Path,
    dataset_dir: Path,
) -> None:
    """One parent run per invocation, a child per loss; every model is registered as a version of
    ``ftfof-<robot>-<loss>``, and the ``use`` model gets the alias."""
    import numpy as np
    import torch

    mlflow = tracking.setup(tracking.experiment_name(params.robot))
    from mlflow.models import infer_signature

    tags = tracking.tags("train")
    parent_tags = {**tags, tracking.MODELS_DIGEST_TAG: models_digest(out)}
    dataset_input = tracking.dataset_input(dataset_dir / "samples.parquet")
    cfg = params.train
    example = data.inputs("validation")[:1]
    requirements = [
        f"torch=={torch.__version__.split('+')[0]}",
        f"mlflow=={mlflow.__version__}",
        f"numpy=={np.__version__}",
    ]
    settings = {
        "train": cfg.model_dump(),
        "dataset": params.dataset.model_dump(),
        "robot": params.robot,
        "surface": params.surface,
        "dataset_digest": data.metadata_digest,
    }
    flat = tracking.flatten(settings)
    with mlflow.start_run(run_name="train", tags=parent_tags):
        mlflow.log_input(dataset_input, context="training")
        mlflow.log_params(flat)
        mlflow.log_metric("wall_seconds", run.summary["wall_seconds"])
        mlflow.log_metrics(
            {
                f"peak_{target}_{model}_{k}": v
                for target, entry in run.summary["peaks"].items()
                for model in ("gp", "gru")
                for k, v in entry[model].items()
                if v == v
            }
        )
        for path in figures:
            mlflow.log_artifact(str(path), artifact_path="figures")
        for r in run.results:
            with mlflow.start_run(
                run_name=r["kind"], nested=True, tags={**tags, "loss": r["kind"]}
            ):
                mlflow.log_input(dataset_input, context="training")
                targets = ",".join(TARGETS)
                mlflow.log_params(
                    {**flat, "targets": targets, "loss": r["kind"], "seed": r["seed"]}
                )
                _log_history(mlflow, r)
                model, output = _model_output(r, cfg, example)
                name = model_name(params.robot, r["kind"])
                info = mlflow.pytorch.log_model(
                    model,
                    name="model",
                    signature=infer_signature(example, output),
                    input_example=example,
                    pip_requirements=requirements,
                    serialization_format="pickle",
                    registered_model_name=name,
                    extra_files=[
                        str(p) for p in (out / weights_file(r["kind"]), out / PEAKS) if p.exists()
                    ],
                )
                client, version = mlflow.MlflowClient(), str(info.registered_model_version)
                for key, value in weights_tags(out, r["kind"]).items():
                    client.set_model_version_tag(name, version, key, value)
                if r["kind"] == cfg.use:
                    client.set_registered_model_alias(name, cfg.alias, version)


def _log_history(mlflow, result: dict) -> None:
    """Loss per epoch as stepped metrics, in batches MLflow accepts."""
    from mlflow.entities import Metric

    client = mlflow.MlflowClient()
    run_id = mlflow.active_run().info.run_id
    stamp = int(time.time() * 1000)
    batch = [
        Metric(f"{split}_loss", v, stamp, e)
        for split in ("train", "validation")
        for e, v in enumerate(result["history"][split])
    ]
    for start in range(0, len(batch), 900):
        client.log_batch(run_id, metrics=batch[start : start + 900])
    mlflow.log_metrics(
        {f"val_{t}_{k}": v for t, m in result["metrics"].items() for k, v in m.items()}
    )
    mlflow.log_metric("best_epoch", result["history"]["best_epoch"])


def _model_output(result: dict, cfg: Train, example):
    """The trained model as a torch module and its output on ``example`` (for the signature)."""
    import torch

    from ftfof.surrogate.model import ForceGRU, ModelConfig

    model = ForceGRU(
        ModelConfig(hidden=cfg.hidden, layers=cfg.layers, dropout=cfg.dropout, outputs=len(TARGETS))
    )
    model.load_state_dict({k: torch.from_numpy(v) for k, v in result["state"].items()})
    model.eval()
    with torch.no_grad():
        return model, model(torch.from_numpy(example)).numpy()
