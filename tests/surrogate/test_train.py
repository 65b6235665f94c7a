"""Training: deterministic on CPU for a seed, learns, and stops early."""

import numpy as np
import pytest
import torch

from ftfof import config
from ftfof.surrogate.train import LOSSES, loss_fn, train_model, validation_metrics

NAMES = ("pull", "jitter")  # one DILATE target, one MSE target


def _toy(n: int, seed: int):
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(n, 20, 4)).astype(np.float32)
    force = np.maximum(np.cumsum(x[..., :1], axis=1) * 0.3, 0)
    spikes = np.maximum(x[..., 1:2], 0) ** 2
    return x, np.concatenate([force, spikes], axis=-1).astype(np.float32)


@pytest.mark.integration  # trains a GRU
def test_training_is_deterministic_and_learns():
    x, y = _toy(48, 0)
    xv, yv = _toy(16, 1)
    settings = config.Train(hidden=8, epochs=6, batch=16, lr=1e-2, patience=6)
    a = train_model(x, y, xv, yv, "mse", settings, 3, NAMES)
    b = train_model(x, y, xv, yv, "mse", settings, 3, NAMES)
    for key, value in a.model.state_dict().items():
        torch.testing.assert_close(value, b.model.state_dict()[key], rtol=0, atol=0)
    assert a.history.validation == b.history.validation
    assert a.history.validation[-1] < a.history.validation[0]


@pytest.mark.integration  # trains a GRU
def test_dilate_training_runs_and_early_stopping_keeps_the_best_epoch():
    x, y = _toy(32, 2)
    xv, yv = _toy(8, 3)
    settings = config.Train(hidden=8, epochs=30, batch=16, lr=0.5, patience=2, gamma=0.1)
    trained = train_model(x, y, xv, yv, "dilate", settings, 1, NAMES)
    h = trained.history
    assert len(h.train) < 30  # a huge learning rate stalls; patience 2 stops it
    assert h.validation[h.best_epoch] == min(h.validation)


def test_validation_metrics_on_a_hand_made_case():
    truth = np.zeros((2, 10))
    truth[:, 4] = 5.0
    pred = np.zeros((2, 10))
    pred[:, 6] = 4.0
    m = validation_metrics(pred, truth, dt=0.01)
    assert m["n"] == 2
    assert m["peak_error_median"] == 1.0
    assert m["peak_time_error_median"] == 0.02
    assert m["mse"] == (25 + 16) / 10


def test_every_loss_params_allow_has_a_criterion_and_an_unknown_one_is_refused():
    settings = config.Train()
    pred, target = torch.zeros(2, 5, 2), torch.ones(2, 5, 2)
    assert set(LOSSES) == {"dilate", "mse"}
    for kind in LOSSES:
        assert torch.isfinite(loss_fn(kind, settings, NAMES)(pred, target))
    with pytest.raises(ValueError, match=r"unknown loss 'mae' \(known: dilate, mse\)"):
        loss_fn("mae", settings, NAMES)


@pytest.mark.parametrize("kind", LOSSES)
def test_a_missing_target_is_masked_out_not_learnt_as_zero(kind):
    """A sample without a target (NaN) adds nothing to the loss and no gradient to it."""
    settings = config.Train(gamma=0.1)
    pred = torch.rand(3, 6, 2, dtype=torch.float64, requires_grad=True)
    target = torch.rand(3, 6, 2, dtype=torch.float64)
    crit = loss_fn(kind, settings, NAMES)
    gappy = target.clone()
    gappy[2] = torch.nan  # the third sample supplies neither target
    loss = crit(pred, gappy)
    loss.backward()
    assert torch.isfinite(loss) and torch.all(pred.grad[2] == 0)
    assert loss.item() != pytest.approx(crit(pred.detach(), target).item())


def test_mse_weighs_each_target_on_its_own_samples():
    pred = torch.zeros(2, 4, 2)
    target = torch.tensor([[[1.0, 2.0]] * 4, [[1.0, float("nan")]] * 4])
    assert loss_fn("mse", config.Train(), NAMES)(pred, target).item() == pytest.approx(1 + 4)


@pytest.mark.integration  # trains a GRU
def test_a_warm_start_fine_tunes_from_its_weights_and_never_returns_worse():
    x, y = _toy(48, 0)
    xv, yv = _toy(16, 1)
    settings = config.Train(hidden=8, epochs=6, batch=16, lr=1e-2, patience=6)
    trained = train_model(x, y, xv, yv, "mse", settings, 3, NAMES)
    state = {k: v.numpy() for k, v in trained.model.state_dict().items()}
    # fine-tuning from those weights starts where they are, not from a fresh initialisation
    one = settings.model_copy(update={"epochs": 1})
    tuned = train_model(x, y, xv, yv, "mse", one, 4, NAMES, warm_start=state)
    assert tuned.history.validation[0] < trained.history.validation[0]
    # a step so large it can only do harm: the warm-start weights come back untouched
    harmful = settings.model_copy(update={"epochs": 2, "lr": 50.0})
    kept = train_model(x, y, xv, yv, "mse", harmful, 4, NAMES, warm_start=state)
    assert kept.history.best_epoch == -1
    for key, value in kept.model.state_dict().items():
        np.testing.assert_array_equal(value.numpy(), state[key])
