"""Statistics the surrogates' checks share."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.stats import spearmanr


def rank_rho(predicted: NDArray[np.float64], simulated: NDArray[np.float64]) -> float:
    """Spearman's rho; NaN with fewer than 3 points or a constant column (no ranking to test)."""
    varied = len(predicted) >= 3 and np.ptp(predicted) > 0 and np.ptp(simulated) > 0
    return float(spearmanr(predicted, simulated).statistic) if varied else float("nan")
