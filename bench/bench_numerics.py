"""What the pinned numerical code paths cost: the same work under the pinned environment
(`stages.runtime.PINNED_X86_64`: numba for x86-64-v3, ATen's AVX2 kernels, MKL's COMPATIBLE
branch) and under the host's native paths, each in a fresh process (the libraries read the
settings once, at load).

Work timed, one thread each: a training step of the surrogate on our compiled layers
(ftfof.surrogate.layers, what `train` runs) and the same step on torch's nn.GRU and nn.Linear
(MKL: what `train` ran before, native on the host, bit-identical only across Intel CPUs); the
compiled GRU population kernel the optimiser calls every generation (numba), and DILATE forward
+ backward (numba). The paper-scale step: hidden 32, one layer, batch 32, N = 100, 7 targets.
Run: python bench/bench_numerics.py
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _train_step(model, x, y):
    import torch

    opt = torch.optim.Adam(model.parameters(), lr=1e-3)

    def step() -> None:
        opt.zero_grad()
        torch.nn.functional.mse_loss(model(x), y).backward()
        opt.step()

    return step


def _torch_force_gru(hidden: int, outputs: int):
    """ForceGRU's shape on torch's own layers (the path `train` no longer takes)."""
    import torch
    from torch import nn

    class TorchForceGRU(nn.Module):
        def __init__(self):
            super().__init__()
            self.gru = nn.GRU(4, hidden, batch_first=True)
            self.head = nn.Linear(hidden, outputs)

        def forward(self, x: torch.Tensor) -> torch.Tensor:
            return nn.functional.softplus(self.head(self.gru(x)[0]))

    return TorchForceGRU()


def _child() -> None:
    """Time the workloads in this process (its environment decides the code paths)."""
    import numba
    import numpy as np
    import torch

    from bench.common import best_of
    from ftfof.surrogate.dilate import dilate_loss
    from ftfof.surrogate.model import ForceGRU, ModelConfig
    from ftfof.surrogate.predict import GRUWeights

    torch.set_num_threads(1)
    numba.set_num_threads(1)
    torch.manual_seed(0)
    model = ForceGRU(ModelConfig(hidden=32, layers=1, outputs=7))
    x = torch.randn(32, 100, 4)
    y = torch.rand(32, 100, 7)
    ours = _train_step(model, x, y)
    theirs = _train_step(_torch_force_gru(32, 7), x, y)

    weights = GRUWeights.from_state({k: v.detach().numpy() for k, v in model.state_dict().items()})
    population = np.random.default_rng(0).normal(size=(200, 100, 4)).astype(np.float32)
    pred = torch.randn(32, 100, 1, dtype=torch.float64, requires_grad=True)
    target = torch.randn(32, 100, 1, dtype=torch.float64)

    def dilate_step() -> None:
        pred.grad = None
        dilate_loss(pred, target, 0.5, 0.01)[0].backward()

    print(
        json.dumps(
            {
                "train step, ftfof layers (numba)": best_of(ours, 5, 5),
                "train step, torch nn.GRU (MKL)": best_of(theirs, 5, 5),
                "GRU population kernel (numba, 200 x 100)": best_of(
                    lambda: weights(population), 5, 5
                ),
                "DILATE fwd+bwd (numba, B=32, N=100)": best_of(dilate_step, 5, 3),
            }
        )
    )


def _run(env: dict[str, str]) -> dict[str, float]:
    out = subprocess.run(
        [sys.executable, __file__, "--child"], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    from stages.runtime import PINNED_X86_64

    host = {k: v for k, v in os.environ.items() if k not in PINNED_X86_64}
    native, pinned = _run(host), _run({**host, **PINNED_X86_64})
    print(f"{'work':<44} {'native ms':>10} {'pinned ms':>10} {'pinned/native':>14}")
    for name, seconds in native.items():
        ratio = pinned[name] / seconds
        print(f"{name:<44} {seconds * 1e3:10.3f} {pinned[name] * 1e3:10.3f} {ratio:13.2f}x")
    ours, theirs = "train step, ftfof layers (numba)", "train step, torch nn.GRU (MKL)"
    print(
        f"training step, pinned ftfof layers / native torch: {pinned[ours] / native[theirs]:.2f}x"
    )


if __name__ == "__main__":
    _child() if "--child" in sys.argv else main()
