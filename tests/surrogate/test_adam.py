"""Adam with an IEEE square root: torch's update, step for step, in the last bits aside."""

import numpy as np
import torch

from ftfof.surrogate.adam import Adam


def _run(optimizer_of, steps: int = 5) -> list[np.ndarray]:
    torch.manual_seed(3)
    weights = [torch.nn.Parameter(torch.randn(7, 5)), torch.nn.Parameter(torch.randn(5))]
    optimizer = optimizer_of(weights)
    for k in range(steps):
        optimizer.zero_grad()
        loss = (weights[0] @ weights[1] - float(k)).pow(2).sum() + weights[1].abs().sum()
        loss.backward()
        optimizer.step()
    return [w.detach().numpy().copy() for w in weights]


def test_it_takes_torchs_adam_steps_with_weight_decay():
    ours = _run(lambda p: Adam(p, lr=1e-2, weight_decay=1e-3))
    torchs = _run(lambda p: torch.optim.Adam(p, lr=1e-2, weight_decay=1e-3, foreach=False))
    for a, b in zip(ours, torchs, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-7)
    start = _run(lambda p: Adam(p, lr=1e-2), steps=0)
    assert all(np.abs(a - s).max() > 1e-3 for a, s in zip(ours, start, strict=True))


def test_its_square_root_is_numpys_correctly_rounded_one():
    """The second moment's root is np.sqrt's: one step from zero state moves each weight by
    lr * g / (sqrt((1 - b2) g^2) / sqrt(1 - b2) + eps), exactly as NumPy computes it."""
    torch.manual_seed(0)
    w = torch.nn.Parameter(torch.randn(1000))
    g = torch.rand(1000) * 10.0 ** torch.randint(-6, 3, (1000,)).float()
    w.grad = g.clone()
    before = w.detach().numpy().copy()
    Adam([w], lr=0.1).step()
    gn = g.numpy()
    m = np.float32(0.1) * gn  # exp_avg after one lerp from 0: (1 - b1) g
    v = (np.float32(0.0) + gn * gn * np.float32(1 - 0.999)).astype(np.float32)
    denom = (np.sqrt(v) / np.float32((1 - 0.999) ** 0.5)).astype(np.float32) + np.float32(1e-8)
    expected = before - np.float32(0.1 / (1 - 0.9)) * (m / denom)
    np.testing.assert_allclose(w.detach().numpy(), expected, rtol=2e-6)
