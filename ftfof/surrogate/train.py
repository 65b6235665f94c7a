"""Training one multi-output surrogate with DILATE or MSE, and its validation metrics (FTFOF §IV.B).

The criterion is a sum over the targets, each on the samples that supply it (NaN = masked):

- ``mse``: the mean squared error of every target;
- ``dilate``: DILATE on the force series (:data:`DILATE_TARGETS`, where the timing and shape of
  a peak are what fs1-fs3 read), divided by N so that it is a per-step error like the MSE of the
  other targets (fs7's running total, body acceleration, film curvature: maxima and totals of
  sparse, event-locked events, for which a shape-only, shift-tolerant loss has nothing to offer
  and a soft-DTW of spikes is ill-posed). The force series share one alignment: DILATE runs on
  them as one multivariate series (D[i, j] = the squared distance of the force vectors), since
  they are the same foot's forces on one time line, and one alignment costs a third of three. A
  sample that lacks one of them is left out of this term.

Deterministic for a seed (seeded init and shuffling, deterministic algorithms) and the same bits
on any x86-64 CPU and thread count: the GRU and its head run on compiled kernels of our own
(:mod:`ftfof.surrogate.layers`), never MKL. Always on the CPU: a hidden-32 GRU gains nothing from
a GPU, and a GPU's kernels would train other weights.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import get_args

import numpy as np
import torch
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.surrogate.adam import Adam
from ftfof.surrogate.dilate import dilate_loss, soft_dtw
from ftfof.surrogate.model import ForceGRU, ModelConfig

Array = NDArray[np.float64]
DTW_GAMMA = 1e-4  # soft-DTW this sharp is hard DTW to within its smoothing
LOSSES: tuple[str, ...] = get_args(config.Loss)
DILATE_TARGETS = ("pull", "Fd", "Fp")  # the force series; every other target trains on MSE
Criterion = Callable[[torch.Tensor, torch.Tensor], torch.Tensor]  # (pred, target) -> loss


@dataclass
class History:
    train: list[float] = field(default_factory=list)
    validation: list[float] = field(default_factory=list)
    best_epoch: int = 0


@dataclass
class Trained:
    model: ForceGRU
    history: History
    seconds: float


def masked_mse(pred: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
    """(K,) mean squared error per target over the finite target entries (0 where none)."""
    mask = torch.isfinite(target)
    diff = torch.where(mask, pred - torch.nan_to_num(target), torch.zeros_like(pred))
    return (diff**2).sum(dim=(0, 1)) / mask.sum(dim=(0, 1)).clamp(min=1)


def loss_fn(kind: str, settings: config.Train, targets: Sequence[str]) -> Criterion:
    """The training criterion ``kind`` over (B, N, K) predictions and targets (NaN = missing);
    an unknown name is an error, never a silent MSE."""
    if kind == "mse":
        return lambda pred, target: masked_mse(pred, target).sum()
    if kind != "dilate":
        raise ValueError(f"unknown loss {kind!r} (known: {', '.join(LOSSES)})")
    shaped = [k for k, n in enumerate(targets) if n in DILATE_TARGETS]
    plain = [k for k in range(len(targets)) if k not in shaped]

    def criterion(pred: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
        B, N, _ = pred.shape
        p, y = pred[..., shaped], target[..., shaped]
        rows = torch.isfinite(y).all(dim=(1, 2))
        loss = masked_mse(pred[..., plain], target[..., plain]).sum()
        if rows.any():
            value = dilate_loss(p[rows], y[rows], settings.alpha, settings.gamma)[0]
            loss = loss + value * (int(rows.sum()) / B) / N  # per step, like the MSE terms
        return loss

    return criterion


def train_model(
    x_train: Array,
    y_train: Array,
    x_val: Array,
    y_val: Array,
    kind: str,
    settings: config.Train,
    seed: int,
    targets: Sequence[str],
    on_epoch: Callable[[int, float, float], None] | None = None,
    warm_start: dict[str, NDArray] | None = None,
) -> Trained:
    """Fit one ForceGRU (inputs (n, N, 4), targets (n, N, K) named ``targets``, normalised,
    NaN where a sample does not supply one).

    Early stopping keeps the weights of the epoch with the lowest validation loss. ``warm_start``
    (a state dict) fine-tunes those weights instead of a fresh initialisation; they count as epoch
    -1, so fine-tuning that never beats them on validation returns them unchanged.
    """
    import time

    started = time.perf_counter()
    model = _initial_model(settings, len(targets), seed, warm_start)
    opt = Adam(model.parameters(), lr=settings.lr, weight_decay=settings.weight_decay)
    crit = loss_fn(kind, settings, targets)
    xt, yt = torch.tensor(x_train), torch.tensor(y_train)
    xv, yv = torch.tensor(x_val), torch.tensor(y_val)
    gen = torch.Generator().manual_seed(seed)
    history = History()
    best, best_state, waited = np.inf, copy.deepcopy(model.state_dict()), 0
    if warm_start is not None:
        best = _validation_loss(model, crit, xv, yv)
        history.best_epoch = -1
    for epoch in range(settings.epochs):
        history.train.append(_train_epoch(model, opt, crit, xt, yt, gen, settings.batch))
        val = _validation_loss(model, crit, xv, yv)
        history.validation.append(val)
        if on_epoch is not None:
            on_epoch(epoch, history.train[-1], val)
        if val < best:
            best, best_state, waited, history.best_epoch = (
                val,
                copy.deepcopy(model.state_dict()),
                0,
                epoch,
            )
        else:
            waited += 1
            if waited >= settings.patience:
                break
    model.load_state_dict(best_state)
    model.eval()
    return Trained(model, history, time.perf_counter() - started)


def _initial_model(
    settings: config.Train, outputs: int, seed: int, warm_start: dict[str, NDArray] | None
) -> ForceGRU:
    """The seeded model (deterministic algorithms from here on), or the ``warm_start`` weights:
    seeded first either way, so the shuffling that follows draws the same."""
    torch.manual_seed(seed)
    torch.use_deterministic_algorithms(True)
    model = ForceGRU(
        ModelConfig(
            hidden=settings.hidden,
            layers=settings.layers,
            dropout=settings.dropout,
            outputs=outputs,
        )
    )
    if warm_start is not None:
        model.load_state_dict({k: torch.as_tensor(np.asarray(v)) for k, v in warm_start.items()})
    return model


def _train_epoch(
    model: ForceGRU,
    opt: Adam,
    crit: Criterion,
    xt: torch.Tensor,
    yt: torch.Tensor,
    gen: torch.Generator,
    batch: int,
) -> float:
    """One pass over the training set in ``gen``'s shuffled order; the sample-weighted mean loss."""
    model.train()
    order = torch.randperm(len(xt), generator=gen)
    total, count = 0.0, 0
    for start in range(0, len(order), batch):
        idx = order[start : start + batch]
        opt.zero_grad()
        loss = crit(model(xt[idx]), yt[idx])
        loss.backward()
        opt.step()
        total += loss.item() * len(idx)
        count += len(idx)
    return total / count


def _validation_loss(
    model: ForceGRU,
    crit: Criterion,
    xv: torch.Tensor,
    yv: torch.Tensor,
) -> float:
    """The criterion on the validation set, the model in evaluation mode, no gradients."""
    model.eval()
    with torch.no_grad():
        return float(crit(model(xv), yv))


def predict(model: ForceGRU, x: Array) -> Array:
    """Normalised predictions (n, N, K) for normalised inputs, in one batched pass."""
    with torch.no_grad():
        return model(torch.tensor(x, dtype=torch.float32)).numpy()


def validation_metrics(pred: Array, target: Array, dt: float) -> dict[str, float]:
    """Errors of physical series (n, N) of one target: MSE, DTW, peak value and time errors,
    over the samples that supply the target (``n`` = how many)."""
    rows = np.isfinite(target).all(axis=1)
    pred, target = pred[rows], target[rows]
    if not rows.any():
        return {"n": 0}
    peak_err = np.abs(pred.max(axis=1) - target.max(axis=1))
    time_err = np.abs(pred.argmax(axis=1) - target.argmax(axis=1)) * dt
    dtw = soft_dtw(pred[..., None], target[..., None], DTW_GAMMA)
    return {
        "n": int(rows.sum()),
        "mse": float(np.mean((pred - target) ** 2)),
        "dtw": float(np.mean(dtw)),
        "peak_error_median": float(np.median(peak_err)),
        "peak_error_p90": float(np.percentile(peak_err, 90)),
        "peak_time_error_median": float(np.median(time_err)),
        "peak_time_error_p90": float(np.percentile(time_err, 90)),
    }
