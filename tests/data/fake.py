"""Synthetic acquisition rows for dataset tests (no simulation needed).

A fake sample presses with 5 N, peels with a Gaussian pull of ``peak`` (normal) and 0.4 of it in
shear, loses its bonds over the pull, trips the switch at 0.2 s, rings the body on release and
lands at 1.05 s; its film bends with the pull and its pad rises to 50 mm in the swing, and its
landed pad holds the 6.6 N proof pull where it peeled at under 5 N (NaN ``with_film=False``: a
force log, without the film channels and the proof phase).
"""

from __future__ import annotations

import numpy as np
import pyarrow as pa

from ftfof.data.acquisition import to_table
from ftfof.sim.records import CHANNELS, SampleResult

SWITCH = 0.2  # s


def film_curvature(t: np.ndarray, peak: float) -> np.ndarray:
    """1/m: a bend that tightens with the pull (peak 3 N -> radius 10 mm)."""
    return (peak / 3.0) * 100.0 * np.exp(-((t - 0.12) ** 2) / 1e-3)


def film_clearance(t: np.ndarray) -> np.ndarray:
    """m: the pad clear of the wall from its release (0.15 s) to its landing, 50 mm at most."""
    return np.where((t > 0.15) & (t < 1.0), 0.05 * np.sin(np.pi * (t - 0.15) / 0.85), 0.0)


def fake_channels(peak: float, with_film: bool = True) -> dict[str, np.ndarray]:
    t = np.arange(-0.25, 1.25, 1e-3)
    tt = np.clip(t, 0, 1)
    x = 0.12 * (10 * tt**3 - 15 * tt**4 + 6 * tt**5)
    z = 0.04 * 64 * tt**3 * (1 - tt) ** 3
    pull = peak * np.exp(-((t - 0.1) ** 2) / 2e-4)
    fz = np.where(t < 0, -5.0, pull - 5.0 * np.exp(-((t - 1.05) ** 2) / 1e-3))
    fx = np.where(t < 0, 0.0, 0.4 * pull)
    bonds = np.where(t < 0.08, 20.0, np.where(t < 0.15, 10.0, 0.0))
    ring = peak * 3.0 * np.exp(-np.maximum(t - 0.15, 0) / 0.01) * (t >= 0.15)
    ch = {c: np.zeros_like(t) for c in CHANNELS}
    ch.update(
        t=t,
        x_cmd=x,
        z_cmd=z,
        x_foot=x,
        z_foot=z,
        Fx=fx,
        Fz=fz,
        Fx_pad=fx,
        Fz_pad=fz,
        Fd=np.maximum(fz, 0),
        Fp=np.maximum(-fz, 0),
        body_acc=2.0 + ring,
        bonds=bonds,
        switch=(t >= SWITCH).astype(float),
        film_curvature=film_curvature(t, peak) if with_film else np.full_like(t, np.nan),
        film_clearance=film_clearance(t) if with_film else np.full_like(t, np.nan),
    )
    return ch


def fake_result(
    key: str, source: str, sample_id: int, peak: float, status: str = "ok", with_film: bool = True
) -> SampleResult:
    ch = fake_channels(peak, with_film)
    r = SampleResult(key, source, sample_id, status, "" if status == "ok" else "boom", 0.1, ch)
    r.scalars = {"peak_detachment": float(ch["Fd"].max()), "peak_pre_pressure": 5.0}
    if with_film:
        held = peak < 5.0
        r.scalars |= {"proof_pull": 6.6, "held_pull": 6.6 if held else 5.0, "proof_held": held}
    return r


def fake_controls(sample_id: int, peak: float) -> np.ndarray:
    """12 control values of a plausible size, one draw per sample; the first sets the pull's
    peak (10 mm per N), so a model of the peaks has something to learn."""
    X = np.random.default_rng(sample_id).uniform(0.0, 0.06, 12)
    X[0] = 0.01 * peak
    return X


def fake_acquisition(n: int = 40, failed: int = 2, with_film: bool = True) -> pa.Table:
    peaks = [3 + i % 5 for i in range(n)]
    results = [
        fake_result(f"sampled:{i}", "sampled", i, p, with_film=with_film)
        for i, p in enumerate(peaks)
    ]
    results += [
        fake_result(f"sampled:{n + i}", "sampled", n + i, 1.0, "failed") for i in range(failed)
    ]
    results += [
        fake_result(f"baseline:{b}:0", f"baseline:{b}", 0, 7.0) for b in ("polynomial", "cycloidal")
    ]
    sampled = zip(results[:n], peaks, strict=True)  # the failed and baselines have none
    controls = {r.key: fake_controls(r.sample_id, p) for r, p in sampled}
    return to_table(results, "mst_m3f", "acrylic", controls, 1.0, with_wall_time=False)
