"""A slip log's friction and adhesion: the estimators on the samples where the pad lets go."""

from __future__ import annotations

import numpy as np

from ftfof.identify.estimate import Estimate, Track, kalman, least_squares
from ftfof.identify.log import SlipLog, slip_samples


def identify(log: SlipLog) -> tuple[Estimate, Track]:
    """Least squares over the slip samples, and the Kalman estimate started from it (the seed's
    filter needs a start near the truth: a window holds one load, so the first windows alone
    cannot give one)."""
    slip = slip_samples(log)
    fn, ft = -log.Fz[slip], np.abs(log.Fx[slip])
    ls = least_squares(fn, ft)
    return ls, kalman(fn, ft, ls)
