"""The x (beta of a plan, alpha of a re-plan) for which every holding pad of a step stays in its
adhesion-shifted friction cone (climbing_slip §3, steps 3 and 5 of
:mod:`ftfof.climb.control.planner`): each phase's weighted least-norm force map, its cone rows,
and the interval their checks r + x q >= 0 leave, with the limits binding its ends named.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.com_step import G, Step
from ftfof.climb.control.forces import wrench_map
from ftfof.errors import FtfofError

Array = NDArray[np.float64]
PHASES = ("pre-swing", "swing", "post-swing")
SIDES = ("pulls off the wall", "slides down the wall", "slides up the wall")
SLACK = 1e-9  # N: a cone value this far below zero holds (rounding, never a real margin)


@dataclass(frozen=True)
class Limit:
    """One cone inequality at its bound on x."""

    foot: str
    phase: str
    side: str  # one of SIDES
    bound: float  # x on the limit (inf: no x satisfies it)

    def __str__(self) -> str:
        return f"{self.foot} {self.side} in {self.phase}"


@dataclass(frozen=True)
class Interval:
    """The x for which every check holds, with the limit binding each end (None: unbounded)."""

    lower: float
    upper: float
    lower_limit: Limit | None
    upper_limit: Limit | None

    @property
    def empty(self) -> bool:
        return self.lower > self.upper

    @property
    def width(self) -> float:
        """upper - lower: negative when empty (how far apart the conflicting limits are)."""
        return self.upper - self.lower


class InfeasibleStepError(FtfofError):
    """No x keeps every holding foot in its cone: the two limits that conflict are named."""

    def __init__(self, interval: Interval):
        lo, hi = interval.lower_limit, interval.upper_limit
        if math.isinf(interval.lower):
            what = f"{lo} whatever the CoM does"
        else:
            what = f"{lo} unless x >= {interval.lower:.4g}, {hi} unless x <= {interval.upper:.4g}"
        super().__init__("CoM plan", what)
        self.interval = interval


@dataclass(frozen=True)
class Phase:
    """One piece, as what the interval and the plan need: its Hermite data (s0, v0, s1, v1)
    = E0 + x E1, its checks' rows (s, s'' at each check = rows @ E) and its stance's force map."""

    index: int  # into PHASES
    start: float  # s, on the step's clock
    duration: float
    E0: Array  # (4,)
    E1: Array  # (4,)
    checks: tuple[Array, Array]  # (P, 4) rows giving s and s'' at the checks
    stance: StanceMap


@dataclass(frozen=True)
class StanceMap:
    """A phase's feet: c = map @ (w + offset), f = c - shift, cone values = cone @ (w + offset)
    for its holding feet (rows side-major), w = (F_x, F_z, M about the goal)."""

    map: Array  # (2n, 3), zero rows for a lifted foot
    shift: Array  # (2n,) (0, F_adh) per holding foot
    offset: Array  # (3,) A @ shift
    cone: Array  # (3k, 3)
    feet: NDArray[np.int64]  # (3k,) the foot of each cone row
    margin: Array  # (3k,) added to each cone value: pull-off - F_adh on the pull rows, else 0


def stance_map(step: Step, phase: int) -> StanceMap:
    """The phase's weighted least-norm force map about the goal and its cone rows."""
    footholds, holds = step.stance(phase)
    n = len(footholds)
    on = np.flatnonzero(holds)
    pos = np.array([footholds[i].position for i in on], float) - step.goal
    mu = np.array([footholds[i].mu for i in on])
    adhesion = np.array([footholds[i].adhesion for i in on])
    weight = np.array([footholds[i].weight for i in on])
    k = len(on)
    A = wrench_map(pos)
    w_inv = np.column_stack([mu * mu, np.ones(k)]).ravel() / np.repeat(weight, 2)
    AW = A * w_inv
    inverse = np.linalg.solve(AW @ A.T, AW).T  # (2k, 3): W^-1 A^T (A W^-1 A^T)^-1
    pull = np.array([footholds[i].pull for i in on])
    shift = np.column_stack([np.zeros(k), adhesion]).ravel()
    tangential, normal = inverse[0::2], inverse[1::2]
    cone = np.concatenate(
        [normal, mu[:, None] * normal - tangential, mu[:, None] * normal + tangential]
    )
    rows = (2 * on[:, None] + np.arange(2)).ravel()
    full_map = np.zeros((2 * n, 3))
    full_map[rows] = inverse
    full_shift = np.zeros(2 * n)
    full_shift[rows] = shift
    margin = np.concatenate([pull - adhesion, np.zeros(2 * k)])
    return StanceMap(full_map, full_shift, A @ shift, cone, np.tile(on, 3), margin)


def interval_of(step: Step, direction: Array, phases: tuple[Phase, ...]) -> Interval:
    """The x whose every phase holds at every check: the checks' tightest bounds."""
    m = step.mass
    w_acc = np.array([m * direction[0], m * direction[1], 0.0])  # per unit s''
    w_arm = np.array([0.0, 0.0, -m * (direction[0] * G[1] - direction[1] * G[0])])  # per unit s
    w_rest = np.array([-m * G[0], -m * G[1], step.momentum_rate])
    r, q, rows = [], [], []
    first = 0  # each phase's first cone row among all phases' rows
    for ph in phases:
        cone = ph.stance.cone
        s_rows, a_rows = ph.checks
        s0, s1 = s_rows @ ph.E0, s_rows @ ph.E1
        a0, a1 = a_rows @ ph.E0, a_rows @ ph.E1
        per_acc, per_arm = cone @ w_acc, cone @ w_arm
        r.append(
            SLACK
            + cone @ (w_rest + ph.stance.offset)
            + ph.stance.margin
            + np.outer(a0, per_acc)
            + np.outer(s0, per_arm)
        )
        q.append(np.outer(a1, per_acc) + np.outer(s1, per_arm))
        rows.append(np.broadcast_to(first + np.arange(len(cone)), q[-1].shape))
        first += len(cone)
    return _bounds(
        np.concatenate([a.ravel() for a in r]),
        np.concatenate([a.ravel() for a in q]),
        np.concatenate([a.ravel() for a in rows]),
        lambda row, bound: _limit(step, phases, row, bound),
    )


def _bounds(
    r: Array, q: Array, rows: NDArray[np.int64], limit: Callable[[int, float], Limit]
) -> Interval:
    """Checks r + x q >= 0: x from the largest -r/q over q > 0 to the smallest over q < 0; a
    check with q = 0 and r < 0 fails for every x. ``limit`` names a check's cone row."""
    never = (q == 0) & (r < 0)
    if never.any():
        failed = limit(int(rows[np.argmax(never)]), math.inf)
        return Interval(math.inf, -math.inf, failed, failed)
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = -r / q
    low = np.where(q > 0, bound, -math.inf)
    high = np.where(q < 0, bound, math.inf)
    i, j = int(np.argmax(low)), int(np.argmin(high))
    lo, hi = float(low[i]), float(high[j])
    return Interval(
        lo,
        hi,
        limit(int(rows[i]), lo) if math.isfinite(lo) else None,
        limit(int(rows[j]), hi) if math.isfinite(hi) else None,
    )


def _limit(step: Step, phases: tuple[Phase, ...], row: int, bound: float) -> Limit:
    """The cone inequality of ``row`` among all phases' cone rows (each phase's side-major)."""
    for ph in phases:
        count = len(ph.stance.cone)
        if row < count:
            foot = step.names[int(ph.stance.feet[row])]
            return Limit(foot, PHASES[ph.index], SIDES[row // (count // 3)], bound)
        row -= count
    raise IndexError(f"cone row {row} past the phases' rows")
