"""The NumPy GRU the optimiser uses computes exactly what the trained torch model computes."""

import numpy as np
import pytest
import torch

from ftfof.surrogate.model import ForceGRU, ModelConfig
from ftfof.surrogate.predict import GRUWeights, with_peak


@pytest.mark.parametrize(("hidden", "layers", "outputs"), [(8, 1, 1), (16, 2, 6)])
def test_numpy_gru_matches_torch(hidden, layers, outputs):
    torch.manual_seed(layers)
    model = ForceGRU(ModelConfig(hidden=hidden, layers=layers, outputs=outputs)).eval()
    x = torch.randn(7, 25, 4)
    with torch.no_grad():
        expected = model(x).double().numpy()
    weights = GRUWeights.from_state({k: v.numpy() for k, v in model.state_dict().items()})
    np.testing.assert_allclose(weights(x.numpy()), expected, rtol=1e-5, atol=1e-6)


def test_with_peak_keeps_the_shape_and_takes_the_peak():
    series = np.array([[0.5, 2.0, 1.0], [0.0, 0.0, 0.0]])
    scaled = with_peak(series, np.array([4.0, 3.0]))
    np.testing.assert_allclose(scaled[0], [1.0, 4.0, 2.0])
    np.testing.assert_allclose(scaled[1], [3.0, 3.0, 3.0])  # no shape: the peak throughout
