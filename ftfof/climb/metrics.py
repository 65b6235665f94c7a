"""What a climb did to the robot, step by step (docs/climb.md).

Per step, in the swing's own time (0 at lift-off), the swinging foot's channels are put in the
platform's shape, so the platform's definitions apply unchanged (:mod:`ftfof.data.targets`):

- ``jitter``: the IMU's peak acceleration from lift-off (first bond break) to complete
  detachment + 50 ms: the platform's ``fsj`` window, FTFOF Table I's body jitter;
- ``jitter_step``: the IMU's peak over the whole step (swing, landing hold, advance);
- ``peak_pull``: the swinging foot's peak pull on the wall while its pad holds;
- ``slip``: how far each stance foot moved along the wall over the step, the largest;
- ``min_bend_radius``: the swinging film's tightest free-span bend, and ``film``, the breach of
  the robot's film limit fc (FTFOF §VI.A.3) when it bends tighter;
- ``pitch_range``: the trunk's pitch, max - min;
- ``torque_ratio``: the largest servo torque over its limit, any leg and joint (over 1: the
  servos could not have held the plan), and ``torque``, which joint and how much;
- ``release``: the platform's release verdict (:func:`ftfof.data.release.release_fault`).

Over the whole climb (:func:`slip_totals`), each stance pad's slip on its wall patch: its
distance, the integral of its speed along the patch while in stance (elastic sway included), and
its peak speed.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.gait import LEGS, Gait
from ftfof.config import LEG_NAMES
from ftfof.data.release import release_fault
from ftfof.data.targets import full_rate

Array = NDArray[np.float64]


@dataclass(frozen=True)
class StepRules:
    """The robot's thresholds a step is read against."""

    switch_height: float  # m: the pad counts as let go once clear of the wall this far
    clearance: float  # m: the robot's swing clearance (the release verdict)
    landing_start: float  # s: T2, where the trajectory's landing segment starts
    torque_limits: Array  # (3,) N m per chain joint (inf: a virtual joint)
    film_limit: float  # m, fc: the film's tightest bend without damage


@dataclass(frozen=True)
class StepMetrics:
    step: int
    leg: int
    jitter: float  # m/s^2
    jitter_step: float  # m/s^2
    peak_pull: float  # N
    landing_press: float  # N, the landed pad's peak press on the wall in its landing hold
    slip: float  # m
    min_bend_radius: float  # m (inf: the film never bent in a free span)
    film: str  # "" within fc, else how tight the film bent
    pitch_range: float  # rad
    torque_ratio: float  # the largest |torque| / limit over every leg's joints
    torque: str  # "" within the limits, else the joint and its torque
    release: str  # "" for a clean release, else what went wrong
    complete: bool  # the step ran to its end (no fall, no stop before it)


def step_channels(c: dict[str, Array], gait: Gait, step: int, switch_height: float) -> dict:
    """The swinging foot's channels of ``step`` in the platform's names, time from lift-off."""
    leg = gait.leg_of(step)
    t0 = gait.lift_off(step)
    inside = (c["t"] >= t0) & (c["t"] < t0 + gait.period)
    t = c["t"][inside] - t0
    bonds = c["bonds"][inside, leg]
    lowest = c["lowest"][inside, leg]
    off = (bonds == 0) & (lowest > switch_height) & (t >= 0)
    switched = np.cumsum(off) > 0
    return {
        "t": t,
        "Fx_pad": c["force"][inside, 2 * leg],
        "Fz_pad": c["force"][inside, 2 * leg + 1],
        "bonds": bonds,
        "switch": switched.astype(float),
        "film_curvature": c["curvature"][inside, leg],
        "film_clearance": np.where(bonds > 0, 0.0, np.maximum(lowest, 0.0)),
    }


def step_metrics(
    c: dict[str, Array],
    imu: dict[str, Array],
    gait: Gait,
    step: int,
    rules: StepRules,
) -> StepMetrics:
    """One step's figures from the climb's channels and its IMU."""
    leg = gait.leg_of(step)
    t0 = gait.lift_off(step)
    ch = step_channels(c, gait, step, rules.switch_height)
    t = ch["t"]
    complete = bool(t.size and t[-1] >= gait.period - 2.0 / max(len(c["t"]) / c["t"][-1], 1.0))
    on_imu = (imu["t"] >= t0) & (imu["t"] < t0 + gait.period)
    acc = np.interp(t + t0, imu["t"], imu["acc"]) if imu["t"].size else np.zeros_like(t)
    T3 = gait.swing
    targets = full_rate({**ch, "body_acc": acc}, T3)
    stance = [k for k in range(LEGS) if k != leg]
    inside = (c["t"] >= t0) & (c["t"] < t0 + gait.period)
    foot_x = c["foot"][inside][:, [2 * k for k in stance]]
    slip = float(np.max(np.abs(foot_x - foot_x[:1]), initial=0.0)) if foot_x.size else 0.0
    pitch = c["body"][inside, 2]
    switched = np.flatnonzero(ch["switch"] > 0)
    switch_time = float(t[switched[0]]) if switched.size else math.inf
    # the landing press: complete detachment to the end of the landing hold, as the platform's
    landing = (t >= switch_time) & (t <= T3 + gait.hold)
    kappa = float(np.max(ch["film_curvature"], initial=0.0))
    return StepMetrics(
        step=step,
        leg=leg,
        jitter=float(np.max(targets["body_acc"], initial=0.0)),
        jitter_step=float(np.max(imu["acc"][on_imu], initial=0.0)),
        peak_pull=float(np.max(targets["pull"], initial=0.0)),
        landing_press=float(np.max(-ch["Fz_pad"][landing], initial=0.0)),
        slip=slip,
        min_bend_radius=1.0 / kappa if kappa > 0 else math.inf,
        film=_film(kappa, rules.film_limit),
        pitch_range=float(np.ptp(pitch)) if pitch.size else 0.0,
        release=release_fault(
            t,
            ch["bonds"],
            switch_time,
            float(np.max(ch["film_clearance"], initial=0.0)),
            rules.clearance,
            rules.landing_start,
        ),
        **_torque(c["torque"][inside], rules.torque_limits),
        complete=complete,
    )


def _film(kappa: float, fc: float) -> str:
    """The film limit's verdict on the step's largest free-span curvature ``kappa`` (1/m)."""
    if kappa * fc <= 1.0:
        return ""
    return f"the film bent to {1e3 / kappa:.1f} mm, tighter than fc = {1e3 * fc:g} mm"


def _torque(torque: Array, limits: Array) -> dict[str, float | str]:
    """The step's largest servo torque against its limit: (T, 4 legs x 3 joints) torques."""
    if torque.size == 0:
        return {"torque_ratio": 0.0, "torque": ""}
    ratio = np.abs(torque) / np.tile(limits, LEGS)
    worst = int(np.argmax(np.max(ratio, axis=0)))
    peak = float(np.max(ratio[:, worst]))
    leg, joint = divmod(worst, 3)
    if peak <= 1.0:
        return {"torque_ratio": peak, "torque": ""}
    need = float(np.max(np.abs(torque[:, worst])))
    return {
        "torque_ratio": peak,
        "torque": f"{LEG_NAMES[leg]}{joint + 1} needs {need:.2f} N m, past its"
        f" {limits[joint]:.2f} N m",
    }


def summary(steps: list[StepMetrics], fell: bool) -> dict[str, float | bool]:
    """The climb's figures: the worst step of each, over the steps that ran to their end."""
    done = [s for s in steps if s.complete]

    def worst(name: str, best: bool = False) -> float:
        values = [getattr(s, name) for s in done]
        if not values:
            return math.nan
        return float(min(values) if best else max(values))

    return {
        "jitter": worst("jitter"),
        "jitter_step": worst("jitter_step"),
        "peak_pull": worst("peak_pull"),
        "slip": worst("slip"),
        "min_bend_radius": worst("min_bend_radius", best=True),
        "pitch_range": worst("pitch_range"),
        "torque_ratio": worst("torque_ratio"),
        "steps_done": float(len(done)),
        "fell": fell,
    }


def as_rows(steps: list[StepMetrics]) -> list[dict]:
    return [asdict(s) for s in steps]


@dataclass(frozen=True)
class SlipTotals:
    """Each stance pad's slip over a climb, per leg (FL FR HL HR).

    The slip distance is how far each pad got from where its stance began, summed over its
    stances: a foot that slides 3 mm and stops has slipped 3 mm, however its film rang on the
    way. The path, |slip velocity| integrated, also counts the pad's elastic sway and the
    film's ringing at every landing and lift-off (+-50 mm/s for a few ms): on the dusty-wall
    scenario it was three times the distance, the same for every controller (issue 40)."""

    distance: Array  # (4,) m: each stance's largest excursion from its start, summed
    path: Array  # (4,) m: |slip velocity| integrated over the recorded climb
    peak: Array  # (4,) m/s: the largest |slip velocity|

    def summary(self) -> dict[str, float]:
        """The climb's figures: the feet's distances and paths summed, the fastest peak."""
        return {
            "slip_distance": float(self.distance.sum()),
            "slip_path": float(self.path.sum()),
            "max_slip_velocity": float(self.peak.max(initial=0.0)),
        }

    def by_foot(self) -> dict[str, dict[str, float]]:
        return {
            leg: {"slip_distance": float(d), "slip_path": float(p), "max_slip_velocity": float(v)}
            for leg, d, p, v in zip(LEG_NAMES, self.distance, self.path, self.peak, strict=True)
        }


def slip_totals(c: dict[str, Array]) -> SlipTotals:
    """:class:`SlipTotals` of a climb's channels (``slip_velocity`` is 0 off the stance, so a
    stance is a run of records where it is not)."""
    v, t = c["slip_velocity"], c["t"]
    peak = np.abs(v).max(axis=0, initial=0.0)
    if t.size < 2:
        return SlipTotals(np.zeros(LEGS), np.zeros(LEGS), peak)
    distance = np.zeros(v.shape[1])
    for leg in range(v.shape[1]):
        travel = np.abs(stance_travel(t, v[:, leg]))
        distance[leg] = sum(travel[a:b].max() for a, b in _stances(v[:, leg]))
    return SlipTotals(distance, np.trapezoid(np.abs(v), t, axis=0), peak)


def stance_travel(t: Array, v: Array) -> Array:
    """One pad's displacement along its patch since its stance began, per record (m; 0 off the
    stance), from its slip velocity ``v``."""
    out = np.zeros_like(v, dtype=float)
    for a, b in _stances(v):
        out[a + 1 : b] = np.cumsum(np.diff(t[a:b]) * (v[a + 1 : b] + v[a : b - 1]) / 2)
    return out


def _stances(v: Array) -> list[tuple[int, int]]:
    """The [start, end) record spans where ``v`` is not 0: one pad's stances."""
    edges = np.flatnonzero(np.diff(np.r_[0, v != 0, 0]))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True))
