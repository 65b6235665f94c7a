"""The compiled GRU's tanh approximation is accurate to float32 rounding."""

import numpy as np

from ftfof.surrogate.gru_kernel import tanh_array


def test_rational_tanh_matches_numpy_over_the_whole_line():
    x = np.concatenate([np.linspace(-12, 12, 200_001), [0.0, -0.0, 1e-8, 40.0, -40.0]])
    x32 = x.astype(np.float32)
    out = np.empty_like(x32)
    tanh_array(x32, out)
    np.testing.assert_allclose(out, np.tanh(x32.astype(np.float64)), rtol=0, atol=5e-7)
    ulp = np.finfo(np.float32).eps
    assert np.all(np.abs(out) <= 1.0 + 2 * ulp)  # bounded and monotone up to float32 rounding
    assert np.all(np.diff(out[:200_001]) >= -4 * ulp)
