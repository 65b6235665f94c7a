"""The surrogates' targets and their objectives, defined once, from an acquisition's channels.

Every target is a series on the dataset's time base (``seq_len`` equal bins over [0, T3 + hold])
computed from the full-rate channels (time from the trajectory start) inside its own window,
0 outside it. The matching objective of the full-rate data is what the same objective function
gives on the binned series, so a predicted and a simulated objective measure the same thing:

- ``pull``: the foot's resultant pull on the pad |(Fx_pad, max(Fz_pad, 0))| while the pad holds
  (t >= 0, bonds intact, before complete detachment); bin maximum -> fs1 = max, fs2 = mean up to
  complete detachment (eq. 10-11 on the resultant, which shearing the pad off cannot escape).
- ``Fd``: the tension alone, same window, bin maximum -> fs1_normal, fs2_normal (the paper's).
- ``Fp``: the pre-pressure on the landing window (complete detachment -> end of the landing
  hold), bin maximum -> fs3 = |max landing pre-pressure - a| (eq. 12).
- ``jitter``: eq. 16 at the full rate on the detachment window (trajectory start -> complete
  detachment + 20 ms): the running sum of the exceedances ReLU(|z_i| - m) of the z-scored second
  derivative of the pull, held after the window; bin maximum -> fs7 = max (the total). The
  simulated fs7 is exactly eq. 16 at the acquisition rate (<= 2 ms), and the surrogate predicts a
  smooth, monotone running total instead of a second derivative of a coarse series or the sparse
  spikes of its density (which it ranked at Spearman 0.5-0.6 on the front).
- ``body_acc``: the body acceleration on lift-off (first bond break) -> complete detachment +
  50 ms, bin maximum -> fsj = max (the IMU jitter of FTFOF Table I, during detachment).
- ``curvature``: the film's free-span curvature (t >= 0), bin maximum -> film safety
  g = fc * max - 1 <= 0.
- ``clearance``: the height of the film's lowest point above the wall (t >= 0; 0 while any of it
  touches), bin maximum -> pad clearance g = 1 - max / required <= 0: the whole pad must rise
  clear of the wall in the swing, or it scuffs along it and lands while still moving.
- ``retouch``: the bonds formed again after complete detachment and before the landing segment
  starts (T2), bin maximum -> g = max / retouch_allowed - 1 <= 0 (the robot's, 0.5 bonds). In
  a quarter of the sampled trajectories the flap springs back about 10 ms after the switch trips
  and one bond holds the wall for about 50 ms, to be peeled again while the foot swings. The
  clearance series cannot show it: the flap's dip comes before the pad first rises clear, and
  its 2 mm are lost in a 50 mm scale.
  A pad that never lets go holds the wall all along: its bonds count from t = 0. Only where the
  record has the bonds and the switch (the 5 % rule can fall before the last bond breaks) and
  the caller gives the landing segment's start.
- ``holds``: 1 on the landing window where the landed pad held the proof pull's F_proof through
  its hold (:mod:`ftfof.sim.proof`, after the record's end), 0 where a tenth of it let go; bin
  maximum -> g = 1 - max / 0.5 <= 0, more likely than not it holds. The held pull itself is no
  target: a pad that holds bears F_proof exactly, one that lets go a little less, so a regression
  on it is read against a cap it never passes; the verdict is what the rule needs.

Complete detachment is the photoelectric switch. A simulated record whose switch never trips
never let go: its pull window runs to the end and it has no landing (its pre-pressure is 0, as
the acquisition's ``landing_pre_pressure``). A record without a switch channel (an imported log)
takes eq. 11's rule on the pull: the first sample after its peak below 5 % of the peak. A target the
record cannot supply (no IMU, no film channel, a force log coarser than 2 ms for the jitter)
is all NaN: the training loss masks it out, nothing is invented.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from ftfof.objectives import DETACHED_FRACTION, jitter_exceedance

Array = NDArray[np.float64]

TARGETS = (
    "pull",
    "Fd",
    "Fp",
    "jitter",
    "body_acc",
    "curvature",
    "clearance",
    "retouch",
    "holds",
)
UNITS = {
    "pull": "N",
    "Fd": "N",
    "Fp": "N",
    "jitter": "",
    "body_acc": "m/s^2",
    "curvature": "1/m",
    "clearance": "m",
    "retouch": "bonds",
    "holds": "",
}
JITTER_TAIL = 0.020  # s of fs7's window after complete detachment
BODY_TAIL = 0.050  # s of fsj's window after complete detachment
JITTER_MAX_STEP = 0.002  # s: a coarser record cannot give eq. 16's second derivative


def edges(T3: float, hold: float, seq_len: int) -> Array:
    return np.linspace(0.0, T3 + hold, seq_len + 1)


def time_base(T3: float, hold: float, seq_len: int) -> Array:
    """Bin centres of ``seq_len`` equal bins over [0, T3 + hold]."""
    e = edges(T3, hold, seq_len)
    return 0.5 * (e[:-1] + e[1:])


def _bin_index(t: Array, e: Array) -> tuple[NDArray[np.bool_], NDArray[np.intp]]:
    inside = (t >= e[0]) & (t <= e[-1])
    idx = np.clip(np.searchsorted(e, t[inside], side="right") - 1, 0, len(e) - 2)
    return inside, idx


def bin_max(t: Array, values: Array, T3: float, hold: float, seq_len: int) -> Array:
    """Maximum of ``values`` in each bin of [0, T3 + hold]; empty bins take the interpolation."""
    e = edges(T3, hold, seq_len)
    inside, idx = _bin_index(t, e)
    out = np.full(seq_len, -np.inf)
    np.maximum.at(out, idx, values[inside])
    empty = ~np.isfinite(out)
    if empty.any():
        out[empty] = np.interp(0.5 * (e[:-1] + e[1:])[empty], t, values)
    return out


def pull_force(fx: Array, fz: Array) -> Array:
    """|(Fx, max(Fz, 0))|; a missing tangential channel (NaN) leaves the tension alone (for the
    detachment rule only: the ``pull`` and ``jitter`` targets are then masked, not faked)."""
    tension = np.maximum(fz, 0.0)
    return tension if not np.isfinite(fx).all() else np.hypot(fx, tension)


def detachment_time(t: Array, switch: Array, pull: Array, T3: float) -> float:
    """Complete detachment: the switch (inf when a recorded switch never trips), else the first
    sample after the pull's peak (within the trajectory) below 5 % of the peak, else T3."""
    if np.isfinite(switch).all() and switch.size == t.size:
        on = np.flatnonzero(switch > 0)
        return float(t[on[0]]) if on.size else np.inf
    during = np.flatnonzero((t >= 0) & (t <= T3))
    if during.size == 0:
        return T3
    f = pull[during]
    peak_at = int(np.argmax(f))
    below = np.flatnonzero(f[peak_at:] < DETACHED_FRACTION * f[peak_at])
    return float(t[during[peak_at + below[0]]]) if below.size and f[peak_at] > 0 else T3


def lift_off_time(t: Array, bonds: Array) -> float:
    """The first bond break after the trajectory starts (0 when unknown or never)."""
    during = np.flatnonzero(t >= 0)
    if during.size == 0 or not np.isfinite(bonds[during]).all():
        return 0.0
    broke = np.flatnonzero(bonds[during] < bonds[during[0]])
    return float(t[during[broke[0]]]) if broke.size else 0.0


def full_rate(
    channels: Mapping[str, Array],
    T3: float,
    landing_start: float | None = None,
    proof_held: float = np.nan,
) -> dict[str, Array]:
    """Every target at the acquisition rate, 0 outside its window (``jitter``, a running total,
    holds its total after it), all NaN if not supplied (``retouch`` without ``landing_start``,
    the trajectory's T2; ``holds`` without ``proof_held``, the record's proof verdict)."""
    t = np.asarray(channels["t"], dtype=float)
    nan = np.full_like(t, np.nan)
    fx = np.asarray(channels["Fx_pad"], dtype=float)
    fz = np.asarray(channels["Fz_pad"], dtype=float)
    bonds = np.asarray(channels.get("bonds", nan), dtype=float)
    pull_all = pull_force(fx, fz)
    switch = np.asarray(channels.get("switch", nan), float)
    detached = detachment_time(t, switch, pull_all, T3)
    holding = (t >= 0) & (t <= detached) & ~(bonds <= 0)
    jitter_window = (t >= 0) & (t <= detached + JITTER_TAIL)
    jitter = np.zeros_like(t)
    step = float(np.median(np.diff(t))) if t.size > 1 else np.inf
    shear_seen = np.isfinite(fx).all()  # a single-axis log cannot give the resultant
    if shear_seen and step <= JITTER_MAX_STEP and jitter_window.sum() >= 3:
        jitter[jitter_window] = jitter_exceedance(pull_all[jitter_window], step)
        jitter = np.where(t >= 0, np.cumsum(jitter), 0.0)
    else:
        jitter = nan
    body = np.asarray(channels.get("body_acc", nan), dtype=float)
    body_window = (t >= lift_off_time(t, bonds)) & (t <= detached + BODY_TAIL)
    curvature, clearance = (_film_channel(channels, k, nan) for k in ("curvature", "clearance"))
    switched = switch.size == t.size and np.isfinite(switch).all()
    knows_retouch = landing_start is not None and switched and np.isfinite(bonds).all()
    off_from = detached if np.isfinite(detached) else 0.0  # never let go: held on all along
    return {
        "pull": np.where(holding, pull_all, 0.0) if shear_seen else nan,
        "Fd": np.where(holding, np.maximum(fz, 0.0), 0.0),
        "Fp": np.where(t >= detached, np.maximum(-fz, 0.0), 0.0),
        "jitter": jitter,
        "body_acc": np.where(body_window, body, 0.0) if np.isfinite(body).all() else nan,
        "curvature": np.where(t >= 0, curvature, 0.0) if np.isfinite(curvature).all() else nan,
        "clearance": np.where(t >= 0, clearance, 0.0) if np.isfinite(clearance).all() else nan,
        "retouch": (
            np.where((t > off_from) & (t < landing_start), bonds, 0.0) if knows_retouch else nan
        ),
        "holds": np.where(t >= detached, proof_held, 0.0) if np.isfinite(proof_held) else nan,
    }


def _film_channel(channels: Mapping[str, Array], name: str, nan: Array) -> Array:
    """``film_<name>``, all NaN when the record does not have it (a force log, an acquisition
    from before the channel)."""
    values = np.asarray(channels.get(f"film_{name}", nan), dtype=float)
    return values if values.size == nan.size else nan


def binned(
    channels: Mapping[str, Array],
    T3: float,
    hold: float,
    seq_len: int,
    landing_start: float | None = None,
    proof_held: float = np.nan,
) -> dict[str, Array]:
    """Every target on the dataset time base: (seq_len,) each, all NaN where not supplied."""
    t = np.asarray(channels["t"], dtype=float)
    out = {}
    for name, values in full_rate(channels, T3, landing_start, proof_held).items():
        if not np.isfinite(values).all():
            out[name] = np.full(seq_len, np.nan)
        else:
            out[name] = bin_max(t, values, T3, hold, seq_len)
    return out
