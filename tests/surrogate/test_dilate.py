"""DILATE against the reference data, torch.gradcheck, plain soft-DTW and degenerate inputs."""

import json

import numpy as np
import pytest
import torch

from ftfof.surrogate.dilate import dilate_loss, soft_alignment, soft_dtw
from ftfof.surrogate.fastmath import exp_neg_array, log_1_3_array
from tests.conftest import DATA

CASES = DATA / "dilate"


def _cases():
    return json.loads((CASES / "cases.json").read_text())["cases"]


@pytest.mark.parametrize("case", _cases(), ids=lambda c: c["file"])
def test_matches_the_reference_values_gradient_and_alignment(case):
    z = np.load(CASES / case["file"])
    pred = torch.tensor(z["pred"], dtype=torch.float64, requires_grad=True)
    target = torch.tensor(z["target"], dtype=torch.float64)
    loss, shape, temporal = dilate_loss(pred, target, case["alpha"], case["gamma"])
    for got, key in ((loss, "loss"), (shape, "loss_shape"), (temporal, "loss_temporal")):
        assert got.item() == pytest.approx(float(z[key]), rel=1e-9), key
    loss.backward()
    grad = pred.grad.numpy()
    assert np.abs(grad - z["grad"]).max() / np.abs(z["grad"]).max() < 1e-8
    np.testing.assert_allclose(
        soft_alignment(pred, target, case["gamma"]), z["alignment"], atol=1e-9
    )


@pytest.mark.parametrize(
    ("B", "N", "d", "gamma"), [(2, 5, 1, 0.1), (3, 7, 2, 0.5), (1, 6, 1, 0.01)]
)
def test_gradcheck(B, N, d, gamma):
    gen = torch.Generator().manual_seed(N)
    pred = torch.randn(B, N, d, dtype=torch.float64, generator=gen, requires_grad=True)
    target = torch.randn(B, N, d, dtype=torch.float64, generator=gen)
    for out in range(3):  # the loss and both of its terms
        assert torch.autograd.gradcheck(
            lambda p, o=out: dilate_loss(p, target, 0.5, gamma)[o], (pred,)
        )


def _naive_soft_dtw(x: np.ndarray, y: np.ndarray, gamma: float) -> float:
    D = (y[:, None] - x[None, :]) ** 2
    n, m = D.shape
    R = np.full((n + 1, m + 1), np.inf)
    R[0, 0] = 0.0
    for i in range(1, n + 1):
        for j in range(1, m + 1):
            prev = np.array([R[i - 1, j - 1], R[i - 1, j], R[i, j - 1]])
            R[i, j] = D[i - 1, j - 1] - gamma * np.logaddexp.reduce(-prev / gamma)
    return R[n, m]


def test_alpha_one_is_plain_soft_dtw():
    rng = np.random.default_rng(5)
    x, y = rng.normal(size=(3, 9, 1)), rng.normal(size=(3, 9, 1))
    pred = torch.tensor(x, requires_grad=True)
    loss, shape, _ = dilate_loss(pred, torch.tensor(y), alpha=1.0, gamma=0.2)
    expected = np.mean([_naive_soft_dtw(x[b, :, 0], y[b, :, 0], 0.2) for b in range(3)])
    assert loss.item() == pytest.approx(expected, rel=1e-12)
    assert loss.item() == shape.item()
    np.testing.assert_allclose(
        soft_dtw(x, y, 0.2), [_naive_soft_dtw(x[b, :, 0], y[b, :, 0], 0.2) for b in range(3)]
    )


@pytest.mark.parametrize("kind", ["identical", "constant"])
def test_degenerate_series_give_finite_loss_and_gradient(kind):
    if kind == "identical":
        y = torch.randn(4, 20, 1, dtype=torch.float64)
        pred = y.clone().requires_grad_(True)
    else:
        y = torch.full((4, 20, 1), 3.0, dtype=torch.float64)
        pred = torch.full((4, 20, 1), 3.0, dtype=torch.float64, requires_grad=True)
    loss, shape, temporal = dilate_loss(pred, y, 0.5, 0.01)
    loss.backward()
    assert all(np.isfinite(v.item()) for v in (loss, shape, temporal))
    assert torch.isfinite(pred.grad).all()


def test_float32_inputs_work_and_agree():
    rng = np.random.default_rng(2)
    x, y = rng.normal(size=(2, 12, 1)), rng.normal(size=(2, 12, 1))
    a = dilate_loss(torch.tensor(x), torch.tensor(y))[0].item()
    b = dilate_loss(torch.tensor(x, dtype=torch.float32), torch.tensor(y, dtype=torch.float32))[
        0
    ].item()
    assert b == pytest.approx(a, rel=1e-5)


def test_shape_mismatch_is_rejected():
    with pytest.raises(ValueError, match=r"must both be \(B, N, d\)"):
        dilate_loss(torch.zeros(2, 5, 1), torch.zeros(2, 6, 1))


def test_fast_exp_and_log_are_accurate_on_their_ranges():
    x = np.linspace(0.0, 60.0, 200_001)
    out = np.empty_like(x)
    exp_neg_array(x, out)
    assert np.max(np.abs(out / np.exp(-x) - 1)) < 5e-16
    s = np.linspace(1.0, 3.0, 200_001)
    log_1_3_array(s, out)
    assert np.max(np.abs(out - np.log(s))) < 5e-16
