"""Synthetic acquisition rows for dataset tests (no simulation needed)."""

from __future__ import annotations

import numpy as np
import pyarrow as pa

from ftfof.data.acquisition import to_table
from ftfof.sim.records import CHANNELS, SampleResult


def fake_result(
    key: str, source: str, sample_id: int, peak: float, status: str = "ok"
) -> SampleResult:
    t = np.arange(-0.25, 1.25, 1e-3)
    tt = np.clip(t, 0, 1)
    x = 0.12 * (10 * tt**3 - 15 * tt**4 + 6 * tt**5)
    z = 0.04 * 64 * tt**3 * (1 - tt) ** 3
    fz = np.where(
        t < 0,
        -5.0,
        peak * np.exp(-((t - 0.1) ** 2) / 2e-4) - 5.0 * np.exp(-((t - 1.05) ** 2) / 1e-3),
    )
    ch = {c: np.zeros_like(t) for c in CHANNELS}
    ch.update(
        t=t,
        x_cmd=x,
        z_cmd=z,
        x_foot=x,
        z_foot=z,
        Fz=fz,
        Fz_pad=fz,
        Fd=np.maximum(fz, 0),
        Fp=np.maximum(-fz, 0),
    )
    r = SampleResult(key, source, sample_id, status, "" if status == "ok" else "boom", 0.1, ch)
    r.scalars = {"peak_detachment": float(np.maximum(fz, 0).max()), "peak_pre_pressure": 5.0}
    return r


def fake_acquisition(n: int = 40, failed: int = 2) -> pa.Table:
    results = [fake_result(f"sampled:{i}", "sampled", i, 3 + i % 5) for i in range(n)]
    results += [
        fake_result(f"sampled:{n + i}", "sampled", n + i, 1.0, "failed") for i in range(failed)
    ]
    results += [
        fake_result(f"baseline:{b}:0", f"baseline:{b}", 0, 7.0) for b in ("polynomial", "cycloidal")
    ]
    return to_table(results, "mst_m3f", "acrylic", {}, 1.0, with_wall_time=False)
