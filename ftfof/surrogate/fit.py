"""Fitting the surrogates of a dataset: one multi-output GRU per loss, side by side in processes,
and the GPs of the peaks ``train.peaks`` names; the metrics that compare them.

The algorithm alone (no files, no tracking): the `train` stage and refinement's fine-tuning call
it and keep what it returns their own way.
"""

from __future__ import annotations

import functools
import multiprocessing
import os
import queue
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

from ftfof.config import Train
from ftfof.errors import DataError
from ftfof.seeds import seed_for
from ftfof.stats import rank_rho
from ftfof.surrogate.peaks import (
    NearFront,
    PeakModel,
    PeakPredictor,
    fit_peak_model,
    near_front,
)
from ftfof.surrogate.store import TARGETS, TrainingData
from ftfof.trajectory.bezier import DECISION_NAMES

EpochReport = Callable[[str, int], None]  # (loss, epoch just finished)
MIN_PEAK_ROWS = 3  # training rows with control values and the target a peak GP needs
# the refinement rounds' training rows a local GP near the front needs: its 14 hyperparameters
# are fitted on them (a paper-scale round adds ~43)
MIN_NEAR_FRONT_ROWS = 20


@dataclass
class Training:
    """What a training run produced, for its caller to write and track."""

    results: list[dict[str, Any]]  # one per loss: job, state dict, history, metrics, predictions
    peaks: dict[str, PeakPredictor]  # target -> the GP of its peak
    summary: dict[str, Any]  # the stage's metrics
    wall: float  # seconds


def train_all(
    cfg: Train,
    search_seed: int,
    data: TrainingData,
    *,
    warm_start: Mapping[str, dict[str, np.ndarray]] | None = None,
    peaks_from: Mapping[str, PeakPredictor] | None = None,
    near_front_peaks: Sequence[str] = (),
    on_epoch: EpochReport | None = None,
) -> Training:
    """Train the multi-output model with every loss of ``cfg``, on the same split and seed (from
    ``search_seed``, :attr:`ftfof.config.Params.search_seed`), then the peak models.

    ``warm_start`` maps each loss to the state dict its model fine-tunes from (every loss must be
    there); without it every model starts from its seeded initialisation. ``peaks_from``: peak
    models refitted on ``data`` with their hyperparameters (fine-tuning) instead of fitted anew;
    the ``near_front_peaks`` targets also get a local GP on the refinement rounds' rows
    (:class:`ftfof.surrogate.peaks.NearFront`) once they have :data:`MIN_NEAR_FRONT_ROWS`,
    blended with their broad GP or, without one, with the GRU's maximum. ``on_epoch(loss,
    epoch)`` is called as each model finishes an epoch (a progress bar), also from workers.
    """
    jobs = _jobs(cfg, search_seed, warm_start)
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
            results = run_jobs(jobs, data, cfg, on_epoch)
            peaks = {n: m for fit in fits for n, m in fit.result().items()}
    else:
        results = run_jobs(jobs, data, cfg, on_epoch)
        peaks = fit_peaks(data, cfg.peaks, previous, near_front_peaks)
    wall = time.perf_counter() - started
    return Training(results, peaks, _summary(cfg, data, results, peaks, wall), wall)


def _jobs(
    cfg: Train, search_seed: int, warm_start: Mapping[str, dict[str, np.ndarray]] | None
) -> list[dict]:
    """One job per loss, all on the same seed; each with its loss's ``warm_start`` weights (a
    loss without them is an error)."""
    jobs = [{"kind": k, "seed": seed_for(search_seed, "train", 0)} for k in cfg.losses]
    if warm_start is not None:
        for job in jobs:
            if job["kind"] not in warm_start:
                raise DataError("warm start", f"no weights for the {job['kind']} loss")
            job["warm_start"] = warm_start[job["kind"]]
    return jobs


def _summary(
    cfg: Train,
    data: TrainingData,
    results: list[dict],
    peaks: Mapping[str, PeakPredictor],
    wall: float,
) -> dict[str, Any]:
    """The stage's metrics: each model's epochs and validation metrics, the peak models beside
    the ``cfg.use`` GRU's series maximum, and the wall time."""
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
    return summary


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
        tail = data.normalization.tail(TARGETS.index(name))
        broad = _broad(name, names, previous, X[rows], y[rows], tail)
        local = rows & near
        if name in near_front_peaks and local.sum() >= MIN_NEAR_FRONT_ROWS:
            out[name] = near_front(name, broad, X[local], y[local], tail)
        elif broad is not None:
            out[name] = broad
    return out


def _only(
    name: str, names: Sequence[str], near_front_peaks: Sequence[str]
) -> tuple[list[str], list[str]]:
    """:func:`fit_peaks`'s ``names`` and ``near_front_peaks`` for ``name`` alone."""
    return [name] if name in names else [], [name] if name in near_front_peaks else []


def _broad(
    name: str,
    names: list[str],
    previous: Mapping[str, PeakPredictor],
    X: np.ndarray,
    y: np.ndarray,
    tail: tuple[float, float],
) -> PeakModel | None:
    """The GP of ``name``'s peak over the whole design: refitted with the hyperparameters (and
    tail) it has, fitted anew on the peaks with their ``tail`` tamed if it has none, None if it
    is not one of ``names`` (its series model's maximum stands in for it)."""
    if name not in names:
        return None
    before = previous.get(name)
    if isinstance(before, NearFront):
        before = before.broad
    return fit_peak_model(name, X, y, tail=tail) if before is None else before.refit(X, y)


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


def run_jobs(
    jobs: list[dict], data: TrainingData, cfg: Train, on_epoch: EpochReport | None = None
) -> list[dict]:
    """Train every job, side by side in processes when asked (one torch thread pool each);
    workers report their epochs through a queue this process reads for ``on_epoch``."""
    cores = os.cpu_count() or 1
    workers = min(len(jobs), cores) if cfg.parallel else 1
    threads = cfg.threads or max(1, cores // workers)
    if workers == 1:
        return [_train_one(job, data, cfg, threads, on_epoch) for job in jobs]
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(workers, mp_context=context) as pool:
        if on_epoch is None:
            futures = [pool.submit(_train_one, job, data, cfg, threads) for job in jobs]
            return [f.result() for f in futures]
        with context.Manager() as manager:
            epochs = manager.Queue()
            report = functools.partial(_put, epochs)
            futures = [pool.submit(_train_one, job, data, cfg, threads, report) for job in jobs]
            while True:
                finished = all(f.done() for f in futures)  # before draining: no epoch is lost
                try:
                    while True:
                        on_epoch(*epochs.get(timeout=0.2))
                except queue.Empty:
                    pass
                if finished:
                    return [f.result() for f in futures]


def _put(epochs, loss: str, epoch: int) -> None:
    epochs.put((loss, epoch))


def _train_one(
    job: dict, data: TrainingData, cfg: Train, threads: int, on_epoch: EpochReport | None = None
) -> dict:
    """One job's model, its validation metrics and predictions: a worker process's whole task,
    torch and numba on the ``threads`` it was given."""
    import numba
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
        on_epoch=None if on_epoch is None else lambda epoch, *_: on_epoch(job["kind"], epoch),
    )
    pred = data.normalization.from_model(predict(trained.model, x_va))
    truth = data.normalization.from_model(y_va)
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
