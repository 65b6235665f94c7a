"""The surrogate: trajectory sequence -> target sequences (FTFOF §IV.B, Fig. 4)."""

from __future__ import annotations

from dataclasses import asdict, dataclass

import torch
from torch import nn

from ftfof.surrogate import layers


@dataclass(frozen=True)
class ModelConfig:
    inputs: int = 4  # x, z, vx, vz (normalised)
    hidden: int = 64
    layers: int = 2
    dropout: float = 0.0
    outputs: int = 1  # target series predicted side by side (one head row each)

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


class ForceGRU(nn.Module):
    """Causal GRU over the trajectory, a softplus head per step: every target is >= 0.

    Causal (unidirectional) because a force at time t cannot depend on where the foot goes later.
    One recurrent state feeds all the targets (they are all consequences of the same peel), so K
    targets cost one GRU pass. Input (B, N, 4) normalised trajectory features; output (B, N, K),
    each target divided by its scale. Its layers are torch's GRU and Linear on compiled kernels of
    our own (:mod:`ftfof.surrogate.layers`), so training gives the same weights on any x86-64 CPU.
    """

    def __init__(self, config: ModelConfig):
        super().__init__()
        self.config = config
        self.gru = layers.GRU(
            config.inputs,
            config.hidden,
            num_layers=config.layers,
            dropout=config.dropout if config.layers > 1 else 0.0,
        )
        self.head = layers.Linear(config.hidden, config.outputs)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        h, _ = self.gru(x)
        return nn.functional.softplus(self.head(h))
