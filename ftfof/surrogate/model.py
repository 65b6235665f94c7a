"""The surrogate: trajectory sequence -> target sequences (FTFOF §IV.B, Fig. 4)."""

from __future__ import annotations

from dataclasses import asdict, dataclass

import torch
from torch import nn


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
    each target divided by its scale.
    """

    def __init__(self, config: ModelConfig):
        super().__init__()
        self.config = config
        self.gru = nn.GRU(
            config.inputs,
            config.hidden,
            num_layers=config.layers,
            batch_first=True,
            dropout=config.dropout if config.layers > 1 else 0.0,
        )
        self.head = nn.Linear(config.hidden, config.outputs)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        h, _ = self.gru(x)
        return nn.functional.softplus(self.head(h))
