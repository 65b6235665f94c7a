"""A slip test's log (simulated or from a physical platform) -> a validated :class:`SlipLog`.

Columns t [s], Fx [N] (tangential), Fz [N] (normal, tension positive) and load [N] (the
commanded normal load of each run, compression positive). Every problem is a
:class:`DataError` naming the file, the row (1-based, header = row 1) and the column.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ftfof.errors import DataError
from ftfof.identify.estimate import WINDOW
from ftfof.identify.log import COLUMNS, SlipLog, slip_samples

MIN_SLIP = 2 * WINDOW  # slip samples the Kalman estimator needs to move off its start


def parse_slip(df: pd.DataFrame, source: str) -> SlipLog:
    """The validated log: every column present and finite, time increasing, enough slip."""
    values = {}
    for name in COLUMNS:
        if name not in df.columns:
            raise DataError(source, f"row 1, column {name!r}: missing (a slip log needs it)")
        v = pd.to_numeric(df[name], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise DataError(source, f"row {bad[0] + 2}, column {name!r}: not a finite number")
        values[name] = v
    back = np.flatnonzero(np.diff(values["t"]) <= 0)
    if back.size:
        raise DataError(source, f"row {back[0] + 3}, column 't': time does not increase")
    log = SlipLog(**values)
    slip = slip_samples(log)
    if slip.sum() < MIN_SLIP:
        last = int(np.flatnonzero(slip)[-1]) + 2 if slip.any() else len(df) + 1
        raise DataError(
            source,
            f"row {last}, column 'Fx': {int(slip.sum())} slip samples, the estimator needs "
            f"at least {MIN_SLIP}",
        )
    return log
