"""DILATE forward+backward vs tslearn's SoftDTWLossPyTorch (shape term only), one thread.

Issue 5 goal: full DILATE <= 0.6x tslearn's shape-only time (about <= 30 ms at N = 100 and
<= 120 ms at N = 200, B = 32). Run: python bench/bench_dilate.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numba
import torch

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import best_of, row
from ftfof.surrogate.dilate import dilate_loss

B, GAMMA = 32, 0.01


def _step(pred: torch.Tensor, loss) -> None:
    pred.grad = None
    loss().backward()


def main() -> None:
    torch.set_num_threads(1)
    numba.set_num_threads(1)
    try:
        from tslearn.metrics import SoftDTWLossPyTorch
    except ImportError:
        sys.exit("tslearn is a bench-only extra: pip install -e '.[bench]'")
    for n in (100, 200):
        gen = torch.Generator().manual_seed(n)
        pred = torch.randn(B, n, 1, dtype=torch.float64, generator=gen, requires_grad=True)
        target = torch.randn(B, n, 1, dtype=torch.float64, generator=gen)
        soft = SoftDTWLossPyTorch(gamma=GAMMA)
        base = best_of(lambda p=pred, t=target, f=soft: _step(p, lambda: f(p, t).mean()), repeats=5)
        ours = best_of(
            lambda p=pred, t=target: _step(p, lambda: dilate_loss(p, t, 0.5, GAMMA)[0]), repeats=5
        )
        print(f"B = {B}, N = {n}, one thread, forward + backward")
        print(row("  tslearn SoftDTWLossPyTorch, shape only", base))
        print(row("  ftfof dilate_loss, shape + temporal", ours, base))
        print(f"  ratio ours / tslearn = {ours / base:.2f} (goal <= 0.6)")


if __name__ == "__main__":
    main()
