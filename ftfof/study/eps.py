"""The ε study (ε-Bezier paper, Fig. 15-16): the ε-Bezier baseline run at several truncations ε,
and what each does to the landing and to the body.

ε only re-times the curve (eq. 11); its control points stay, so the sweep is one trajectory
re-timed. ε = 0 is the warp's limit, the identity: the paper's "ordinary bezier method" it
compares against (eq. 11 itself is 0/0 there, hence ``epsilon > 0`` in params.yaml).

Per ε, from the platform's channels:

- the landing impact: the peak pre-pressure after complete detachment (the acquisition's
  ``landing_pre_pressure``) and the peak of its rise rate dFp/dt at the sensor rate (forward
  differences); beside them the pre-pressure the landing settles to, held over the run's last
  50 ms: the seed's "supporting force" the impact falls to at large ε;
- the body jitter: the body's peak acceleration over the whole run (Table I's ``peak_body_acc``,
  landing included) and during detachment only (fsj's window, :mod:`ftfof.data.targets`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from itertools import pairwise

import numpy as np
from numpy.typing import NDArray

from ftfof.data.targets import full_rate
from ftfof.errors import ParamsError, SimulationError
from ftfof.sim.pool import run_all
from ftfof.sim.spec import Bench
from ftfof.trajectory.baselines import EpsBezier

Array = NDArray[np.float64]

EPSILONS = (0.0, 0.5, 1.0, 2.0, 4.0, 8.0)  # the sweep
# the seed's reading of Fig. 16: the impact falls up to ε = 4 and barely moves beyond
KNEE, LAST = 4.0, 8.0
FLAT = 0.10  # "barely": a relative change below this from KNEE to LAST
HELD = 0.050  # s at the end of the landing hold over which the settled pre-pressure is averaged


def parse_epsilons(text: str) -> list[float]:
    """``0,0.5,1`` -> distinct, finite, non-negative values in increasing order."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise ParamsError("--epsilons", f"{text!r} is not comma-separated numbers") from None
    if not all(np.isfinite(v) and v >= 0 for v in values) or len(set(values)) != len(values):
        raise ParamsError("--epsilons", f"need distinct, finite values >= 0 (got {text})")
    return sorted(values)


@dataclass(frozen=True)
class EpsPoint:
    """One ε's landing and body figures."""

    eps: float
    landing_pre_pressure: float  # N
    landing_rate: float  # peak dFp/dt on the landing, N/s
    held_pre_pressure: float  # N, settled at the end of the landing hold
    peak_body_acc: float  # m/s², whole run
    detachment_jitter: float  # m/s², fsj's window
    switch_time: float  # s, complete detachment (a larger ε starts slower)


def swept(trajectory: EpsBezier, epsilons: Sequence[float]) -> list[EpsBezier]:
    """``trajectory`` re-timed at each ε (its control points kept)."""
    return [replace(trajectory, eps=float(e)) for e in epsilons]


def landing_rate(t: Array, Fp: Array, landed: Array) -> float:
    """The peak rise rate of the pre-pressure over the samples ``landed`` (N/s)."""
    rate = np.diff(Fp) / np.diff(t)
    return float(np.max(rate[landed[1:]], initial=0.0))


def measure(
    eps: float, channels: Mapping[str, Array], scalars: Mapping[str, float], T3: float
) -> EpsPoint:
    """One simulated ε's figures, from its channels and its acquisition scalars."""
    t, Fp = np.asarray(channels["t"], float), np.asarray(channels["Fp"], float)
    landed = np.asarray(channels["switch"]) > 0  # the landing_pre_pressure's window
    return EpsPoint(
        eps=float(eps),
        landing_pre_pressure=float(scalars["landing_pre_pressure"]),
        landing_rate=landing_rate(t, Fp, landed),
        held_pre_pressure=float(np.mean(Fp[t >= t[-1] - HELD])),
        peak_body_acc=float(scalars["peak_body_acc"]),
        detachment_jitter=float(np.max(full_rate(channels, T3)["body_acc"])),
        switch_time=float(scalars["switch_time"]),
    )


def trend(points: Sequence[EpsPoint], figure: str = "landing_pre_pressure") -> dict:
    """The seed's claim on ``figure``: it falls at every step of ε up to 4, and changes by less
    than 10 % from 4 to 8. ``None`` where the sweep lacks the values a part needs."""
    by_eps = {p.eps: getattr(p, figure) for p in points}
    up_to = [by_eps[e] for e in sorted(by_eps) if e <= KNEE]
    falls = all(b < a for a, b in pairwise(up_to)) if KNEE in by_eps and len(up_to) > 1 else None
    change = (by_eps[LAST] - by_eps[KNEE]) / by_eps[KNEE] if {KNEE, LAST} <= set(by_eps) else None
    flat = None if change is None else bool(abs(change) < FLAT)
    return {
        "figure": figure,
        "falls_up_to_4": falls,
        "change_4_to_8": change,
        "flat_4_to_8": flat,
        "agrees_with_seed": None if None in (falls, flat) else bool(falls and flat),
    }


def report(points: Sequence[EpsPoint], press_target: float) -> dict:
    """The study as JSON: the points, the press a landing aims at, and the seed's trend on the
    landing impact (its peak and its rate) and on the body."""
    return {
        "press_target": press_target,
        "points": [asdict(p) for p in points],
        "trend": {
            f: trend(points, f) for f in ("landing_pre_pressure", "landing_rate", "peak_body_acc")
        },
    }


@dataclass(frozen=True)
class EpsStudy:
    """The measured points, each ε's landing (time and pre-pressure Fp from complete detachment
    on) and the press a landing aims at."""

    points: list[EpsPoint]
    landings: dict[float, tuple[Array, Array]]
    press: float

    def report(self) -> dict:
        return report(self.points, self.press)


def simulate(on: Bench, base: EpsBezier, epsilons: Sequence[float], workers: int) -> EpsStudy:
    """``base`` re-timed at every ε and simulated on ``on`` in a process pool; a failed
    simulation is an error naming its ε."""
    specs = [
        on.analytic(f"eps:{e:g}", i, trajectory)
        for i, (e, trajectory) in enumerate(zip(epsilons, swept(base, epsilons), strict=True))
    ]
    points: list[EpsPoint] = []
    landings = {}
    for e, r in zip(epsilons, run_all(specs, workers), strict=True):
        if not r.ok:
            raise SimulationError(f"eps_bezier at ε = {e:g}", r.error)
        points.append(measure(e, r.channels, r.scalars, on.robot.timing.T3))
        landed = r.channels["switch"] > 0
        landings[e] = (r.channels["t"][landed], r.channels["Fp"][landed])
    return EpsStudy(points, landings, specs[0].pre_pressure)
