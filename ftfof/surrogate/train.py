"""Training one surrogate with DILATE or MSE, and its validation metrics (FTFOF §IV.B).

Deterministic on CPU for a seed (seeded init and shuffling, deterministic algorithms, a fixed
thread count); uses a GPU when one is present (the DILATE kernel itself runs on the CPU).
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import get_args

import numpy as np
import torch
from numpy.typing import NDArray

from ftfof import config
from ftfof.surrogate.dilate import dilate_loss, soft_dtw
from ftfof.surrogate.model import ForceGRU, ModelConfig

Array = NDArray[np.float64]
DTW_GAMMA = 1e-4  # soft-DTW this sharp is hard DTW to within its smoothing
LOSSES: tuple[str, ...] = get_args(config.Loss)


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


def device() -> torch.device:
    return torch.device("cuda" if torch.cuda.is_available() else "cpu")


def loss_fn(
    kind: str, settings: config.Train
) -> Callable[[torch.Tensor, torch.Tensor], torch.Tensor]:
    """The training criterion ``kind``; an unknown name is an error, never a silent MSE."""
    if kind == "dilate":
        return lambda pred, target: dilate_loss(pred, target, settings.alpha, settings.gamma)[0]
    if kind == "mse":
        return lambda pred, target: torch.mean((pred - target) ** 2)
    raise ValueError(f"unknown loss {kind!r} (known: {', '.join(LOSSES)})")


def train_model(
    x_train: Array,
    y_train: Array,
    x_val: Array,
    y_val: Array,
    kind: str,
    settings: config.Train,
    seed: int,
    on_epoch: Callable[[int, float, float], None] | None = None,
    warm_start: dict[str, NDArray] | None = None,
) -> Trained:
    """Fit one ForceGRU (inputs (n, N, 4), targets (n, N, 1), all normalised).

    Early stopping keeps the weights of the epoch with the lowest validation loss. ``warm_start``
    (a state dict) fine-tunes those weights instead of a fresh initialisation; they count as epoch
    -1, so fine-tuning that never beats them on validation returns them unchanged.
    """
    import time

    started = time.perf_counter()
    torch.manual_seed(seed)
    torch.use_deterministic_algorithms(True)
    dev = device()
    model = ForceGRU(
        ModelConfig(hidden=settings.hidden, layers=settings.layers, dropout=settings.dropout)
    )
    if warm_start is not None:
        model.load_state_dict({k: torch.as_tensor(np.asarray(v)) for k, v in warm_start.items()})
    model = model.to(dev)
    opt = torch.optim.Adam(model.parameters(), lr=settings.lr, weight_decay=settings.weight_decay)
    crit = loss_fn(kind, settings)
    xt, yt = torch.tensor(x_train, device=dev), torch.tensor(y_train, device=dev)
    xv, yv = torch.tensor(x_val, device=dev), torch.tensor(y_val, device=dev)
    gen = torch.Generator().manual_seed(seed)
    history = History()
    best, best_state, waited = np.inf, copy.deepcopy(model.state_dict()), 0
    if warm_start is not None:
        model.eval()
        with torch.no_grad():
            best = float(crit(model(xv), yv))
        history.best_epoch = -1
    for epoch in range(settings.epochs):
        model.train()
        order = torch.randperm(len(xt), generator=gen).to(dev)
        total, count = 0.0, 0
        for start in range(0, len(order), settings.batch):
            idx = order[start : start + settings.batch]
            opt.zero_grad()
            loss = crit(model(xt[idx]), yt[idx])
            loss.backward()
            opt.step()
            total += loss.item() * len(idx)
            count += len(idx)
        model.eval()
        with torch.no_grad():
            val = float(crit(model(xv), yv))
        history.train.append(total / count)
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
    return Trained(model.cpu(), history, time.perf_counter() - started)


def predict(model: ForceGRU, x: Array) -> Array:
    """Normalised predictions (n, N, 1) for normalised inputs, in one batched pass."""
    with torch.no_grad():
        return model(torch.tensor(x, dtype=torch.float32)).numpy()


def validation_metrics(pred: Array, target: Array, dt: float) -> dict[str, float]:
    """Errors of physical force series (n, N): MSE, DTW, peak value and peak time errors."""
    peak_err = np.abs(pred.max(axis=1) - target.max(axis=1))
    time_err = np.abs(pred.argmax(axis=1) - target.argmax(axis=1)) * dt
    dtw = soft_dtw(pred[..., None], target[..., None], DTW_GAMMA)
    return {
        "mse": float(np.mean((pred - target) ** 2)),
        "dtw": float(np.mean(dtw)),
        "peak_error_median": float(np.median(peak_err)),
        "peak_error_p90": float(np.percentile(peak_err, 90)),
        "peak_time_error_median": float(np.median(time_err)),
        "peak_time_error_p90": float(np.percentile(time_err, 90)),
    }
