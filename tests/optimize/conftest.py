"""An untrained but real GRU surrogate: the optimiser's plumbing does not depend on training."""

import pytest
import torch

from ftfof.data.dataset import TARGETS, Normalization
from ftfof.surrogate.model import ForceGRU, ModelConfig
from ftfof.surrogate.predict import GRUWeights, Surrogate


def _weights(seed: int) -> GRUWeights:
    torch.manual_seed(seed)
    model = ForceGRU(ModelConfig(hidden=8, layers=1, outputs=len(TARGETS)))
    return GRUWeights.from_state({k: v.numpy() for k, v in model.state_dict().items()})


@pytest.fixture(scope="session")
def surrogate() -> Surrogate:
    norm = Normalization(
        input_mean=[0.05, 0.01, 0.0, 0.0],
        input_scale=[0.04, 0.02, 0.3, 0.3],
        target_scale=[2.0, 2.0, 3.0, 0.5, 20.0, 50.0, 0.02, 0.3, 0.5],
    )
    return Surrogate(_weights(1), TARGETS, TARGETS, norm, seq_len=32, hold=0.1)
