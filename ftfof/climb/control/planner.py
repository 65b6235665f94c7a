"""One step's CoM plan that keeps every holding pad in its adhesion-shifted friction cone
(climbing_slip §3; the re-plan after a slip, §4.2), for our sagittal robot.

Frame and signs: x up the wall, z out of it, gravity along -x (the climbing model's frame). A
foot's force f = (f_t, f_n) is the wall's force on the foot: f_t along +x, f_n along +z, so
f_n > 0 presses the pad into the wall and f_n < 0 pulls on it. A pad of friction ``mu`` and
adhesion ``F_adh`` holds while

    f_n >= -F_pull                 it does not pull off the wall (F_pull: F_adh unless the
                                   pad's pull-off is given, Foothold.pull_off),
    |f_t| <= mu (f_n + F_adh)      it does not slide (the pyramid is two lines in 2-D),

that is while its adhesion-shifted force c = (f_t, f_n + F_adh) lies in the plain cone: the
paper's contact force beside a constant magnetic one. Moments are a x b = a_x b_z - a_z b_x.

Dynamics: m (p'' - g) = sum f_i and sum (p_i - p) x f_i = L' (the trunk's pitch only enters
through L', given; the feet's frames are the wall's). The method, in the paper's steps:

1. The CoM runs on the line through the goal p_b along d = (p_b - p_a) / |p_b - p_a|:
   p = p_b + s(t) d. Then (p - p_b) x (p'' - g) = -s d x g, and about the goal the wrench the
   feet must give is linear in (s, s''): the cross product's bilinearity is gone.
2. Three cubic Hermite pieces: pre-swing (every foot holds) from p_a at rest, swing (the
   stepping foot off) at constant acceleration alpha d, post-swing (the stepping foot at its
   landing) at constant acceleration beta d to p_b at rest. The ratio gamma = alpha / beta is
   fixed beforehand as the paper fixes it (the swing's largest distance from the goal least),
   leaving one unknown, x = beta (the paper's x = beta d with d fixed along the line: a scalar).
3. Each phase's forces are the weighted least-norm solution of its stance's equations,
   c = W^-1 A^T (A W^-1 A^T)^-1 w, per foot W_i = weight_i diag(1 / mu_i^2, 1): shear shared
   in proportion to mu^2, and normal load balanced about each foot's own cone apex, so a weakly
   adhering foot is pulled on less. Every cone value is then linear in (s, s'').
4. Proposition 1: a phase's cone values hold over the phase if they hold where its time
   functions peak. Swing and post-swing have one, s = x f(t) at a constant s'': the check at
   f's extremes is exact. The pre-swing (and every re-planned piece) has two, so the checks
   are the Bezier control points of the curve (s(t), s''(t)) on ``ARCS`` sub-arcs: the curve
   lies in their convex hull, so holding there is sufficient (a little conservative).
5. Every check is r + x q >= 0: the feasible x form an interval, and the plan takes its point
   nearest zero (the paper's QP, min x^2, in one dimension: closed form).

The re-plan from mid-swing (§4.2.1) keeps the line: the rest of the swing at a constant
acceleration alpha d from the CoM's state, then post-swing the cubic Hermite piece to the goal
at rest, with the feet's new mu and F_adh; x = alpha.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.forces import wrench_map
from ftfof.config import GRAVITY, LEG_NAMES
from ftfof.errors import FtfofError

Array = NDArray[np.float64]
G = np.array([-GRAVITY, 0.0])
PHASES = ("pre-swing", "swing", "post-swing")
SIDES = ("pulls off the wall", "slides down the wall", "slides up the wall")
ARCS = 4  # sub-arcs of a cubic piece's Bezier check (the hull's excess falls as 1 / ARCS^2)
SLACK = 1e-9  # N: a cone value this far below zero holds (rounding, never a real margin)


@dataclass(frozen=True)
class Foothold:
    """One foot on the wall and what holds it there."""

    position: Array  # (2,) the pad's contact point (x, z), m
    mu: float  # friction coefficient
    adhesion: float  # F_adh, N: the cone's shift (the shear capacity seen as normal load)
    weight: float = 1.0  # scales the foot's W_f: a heavier weight gives it less of the load
    pull_off: float | None = None  # N: the most the pad holds pulled off (None: F_adh)

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", np.asarray(self.position, float))
        if self.mu <= 0 or self.adhesion < 0 or self.weight <= 0:
            raise ValueError(f"a foothold needs mu > 0, F_adh >= 0, weight > 0: {self}")
        if self.pull_off is not None and self.pull_off < 0:
            raise ValueError(f"a foothold needs pull-off >= 0: {self}")

    @property
    def pull(self) -> float:
        """The most the pad holds pulled off the wall, N: its pull-off, or F_adh without one."""
        return self.adhesion if self.pull_off is None else float(self.pull_off)


@dataclass(frozen=True)
class Step:
    """One step: the CoM from ``start`` to ``goal`` (at rest at both) while ``feet[swing]``
    moves to ``landing``; pre-swing, swing and post-swing last ``durations``."""

    mass: float  # kg, the whole robot
    start: Array  # (2,) CoM, m
    goal: Array  # (2,) CoM, m
    feet: tuple[Foothold, ...]  # every foot before the step, in ``names`` order
    swing: int  # the stepping foot
    landing: Foothold  # the stepping foot after the step
    durations: tuple[float, float, float]  # s
    momentum_rate: float = 0.0  # L', N m, the centroidal angular momentum's rate
    names: tuple[str, ...] = LEG_NAMES

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", np.asarray(self.start, float))
        object.__setattr__(self, "goal", np.asarray(self.goal, float))
        if len(self.feet) != len(self.names) or not 0 <= self.swing < len(self.feet):
            raise ValueError(f"{len(self.feet)} feet for {self.names}, stepping foot {self.swing}")
        if self.mass <= 0 or min(self.durations) <= 0:
            raise ValueError(
                f"a step needs a mass and durations > 0: {self.mass}, {self.durations}"
            )

    @property
    def direction(self) -> Array:
        """The CoM's line, start to goal; up the wall when the goal is the start."""
        delta = self.goal - self.start
        norm = math.hypot(*delta)
        return delta / norm if norm > 0 else np.array([1.0, 0.0])

    def stance(self, phase: int) -> tuple[tuple[Foothold, ...], NDArray[np.bool_]]:
        """Phase ``phase``'s (an index into PHASES) footholds, the stepping foot at its
        landing after the swing, and which of them hold."""
        feet = list(self.feet)
        if phase == 2:
            feet[self.swing] = self.landing
        holds = np.ones(len(feet), bool)
        holds[self.swing] = phase != 1
        return tuple(feet), holds


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
class _Phase:
    """One piece, as what the interval and the plan need: its Hermite data (s0, v0, s1, v1)
    = E0 + x E1, its checks' rows (s, s'' at each check = rows @ E) and its stance's force map."""

    index: int  # into PHASES
    start: float  # s, on the step's clock
    duration: float
    E0: Array  # (4,)
    E1: Array  # (4,)
    checks: tuple[Array, Array]  # (P, 4) rows giving s and s'' at the checks
    stance: _Stance


@dataclass(frozen=True)
class _Stance:
    """A phase's feet: c = map @ (w + offset), f = c - shift, cone values = cone @ (w + offset)
    for its holding feet (rows side-major), w = (F_x, F_z, M about the goal)."""

    map: Array  # (2n, 3), zero rows for a lifted foot
    shift: Array  # (2n,) (0, F_adh) per holding foot
    offset: Array  # (3,) A @ shift
    cone: Array  # (3k, 3)
    feet: NDArray[np.int64]  # (3k,) the foot of each cone row
    margin: Array  # (3k,) added to each cone value: pull-off - F_adh on the pull rows, else 0


@dataclass(frozen=True)
class ComPlan:
    """A planned CoM over the step's clock and the weighted-inverse forces that carry it."""

    step: Step
    direction: Array  # (2,) d
    x: float  # beta (a plan) or alpha (a re-plan), m/s^2 along d
    interval: Interval
    phases: tuple[str, ...]  # each piece's phase
    starts: Array  # (P,) s
    end: float  # s
    coefficients: Array = field(repr=False)  # (P, 4) s(tau) = sum c_k tau^k per piece
    maps: Array = field(repr=False)  # (P, 2n, 3)
    shifts: Array = field(repr=False)  # (P, 2n)
    offsets: Array = field(repr=False)  # (P, 3)

    def _along(self, t: Array) -> tuple[NDArray[np.int64], Array, Array, Array]:
        """Each time's piece and s, s', s'' there."""
        t = np.asarray(t, float)
        if t.min() < self.starts[0] - 1e-12 or t.max() > self.end + 1e-12:
            raise ValueError(f"the plan covers [{self.starts[0]}, {self.end}] s only")
        k = np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, len(self.starts) - 1)
        tau = t - self.starts[k]
        c = self.coefficients[k]
        s = c[:, 0] + tau * (c[:, 1] + tau * (c[:, 2] + tau * c[:, 3]))
        v = c[:, 1] + tau * (2 * c[:, 2] + 3 * tau * c[:, 3])
        a = 2 * c[:, 2] + 6 * tau * c[:, 3]
        return k, s, v, a

    def state(self, t: Array) -> tuple[Array, Array, Array]:
        """CoM position, velocity and acceleration at times ``t`` (N,), each (N, 2)."""
        _, s, v, a = self._along(t)
        d = self.direction
        return self.step.goal + s[:, None] * d, v[:, None] * d, a[:, None] * d

    def forces(self, t: Array) -> Array:
        """(N, n, 2) every foot's (f_t, f_n) at times ``t``; zero for the lifted foot. The
        wrench is the exact one of the planned CoM (no linearisation)."""
        k, s, _, a = self._along(t)
        m, d = self.step.mass, self.direction
        pull = a[:, None] * d - G  # p'' - g
        arm = s[:, None] * d  # p - goal
        moment = self.step.momentum_rate + m * (arm[:, 0] * pull[:, 1] - arm[:, 1] * pull[:, 0])
        w = np.column_stack([m * pull, moment]) + self.offsets[k]
        c = np.einsum("nij,nj->ni", self.maps[k], w) - self.shifts[k]
        return c.reshape(len(k), -1, 2)


def accel_ratio(swing: float, post: float) -> float:
    """gamma = alpha / beta < 0 whose swing strays least from the goal: the swing's peak
    distance (at its turning point) equals its distance at lift-off, the root of
    T2^2 gamma^2 / 2 + T3 (T2 + T3) gamma - T3^2 / 2 = 0 below zero."""
    b = post * (swing + post)
    return (-b - math.sqrt(b * b + (swing * post) ** 2)) / swing**2


def _hermite_rows(tau: Array, T: float) -> tuple[Array, Array, Array]:
    """Rows giving s, s' and s'' at local times ``tau`` of a cubic Hermite piece of duration
    T from its data (s0, v0, s1, v1), each (N, 4)."""
    u = np.asarray(tau, float) / T
    u2, u3 = u * u, u * u * u
    value = np.stack([1 - 3 * u2 + 2 * u3, T * (u - 2 * u2 + u3), 3 * u2 - 2 * u3, T * (u3 - u2)])
    rate = np.stack([6 * (u2 - u) / T, 1 - 4 * u + 3 * u2, 6 * (u - u2) / T, 3 * u2 - 2 * u])
    acc = np.stack([(12 * u - 6) / T**2, (6 * u - 4) / T, (6 - 12 * u) / T**2, (6 * u - 2) / T])
    return value.T, rate.T, acc.T


def _points(tau: Array, T: float) -> tuple[Array, Array]:
    """Checks on the curve itself at ``tau``: exact where one time function peaks there."""
    value, _, acc = _hermite_rows(tau, T)
    return value, acc


def _hull(T: float, arcs: int = ARCS) -> tuple[Array, Array]:
    """Checks at the Bezier control points of (s, s'') on ``arcs`` equal sub-arcs: s cubic,
    s'' linear raised to degree 3, so the curve lies in their convex hull."""
    knots = np.linspace(0.0, T, arcs + 1)
    value, rate, acc = _hermite_rows(knots, T)
    h = (T / arcs) / 3
    a0, a1 = acc[:-1], acc[1:]
    s_rows = np.stack([value[:-1], value[:-1] + h * rate[:-1], value[1:] - h * rate[1:]], 1)
    a_rows = np.stack([a0, (2 * a0 + a1) / 3, (a0 + 2 * a1) / 3], 1)
    s_rows = np.concatenate([s_rows.reshape(-1, 4), value[-1:]])
    return s_rows, np.concatenate([a_rows.reshape(-1, 4), acc[-1:]])


def _stance(step: Step, phase: int) -> _Stance:
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
    return _Stance(full_map, full_shift, A @ shift, cone, np.tile(on, 3), margin)


def _interval(step: Step, direction: Array, phases: tuple[_Phase, ...]) -> Interval:
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


def _limit(step: Step, phases: tuple[_Phase, ...], row: int, bound: float) -> Limit:
    """The cone inequality of ``row`` among all phases' cone rows (each phase's side-major)."""
    for ph in phases:
        count = len(ph.stance.cone)
        if row < count:
            foot = step.names[int(ph.stance.feet[row])]
            return Limit(foot, PHASES[ph.index], SIDES[row // (count // 3)], bound)
        row -= count
    raise IndexError(f"cone row {row} past the phases' rows")


def _plan_phases(step: Step) -> tuple[_Phase, ...]:
    """Pre-swing, swing and post-swing with x = beta (alpha = gamma beta): Hermite data and
    checks. Swing and post-swing are s = beta f(t) at constant s'': checked where f peaks
    (its ends and, in the swing, its turning point); the pre-swing on its Bezier hull."""
    T1, T2, T3 = step.durations
    gamma = accel_ratio(T2, T3)
    lift = np.array([T3 * T3 / 2 + T3 * T2 + gamma * T2 * T2 / 2, -(T3 + gamma * T2)])  # / beta
    land = np.array([T3 * T3 / 2, -T3])  # the post-swing's start, s and s', per unit beta
    distance = float(np.dot(step.goal - step.start, step.direction))
    turn = T2 + T3 / gamma  # the swing's turning point, inside it (gamma < -T3 / T2)
    zero = np.zeros(4)
    return (
        _Phase(
            0,
            0.0,
            T1,
            np.array([-distance, 0, 0, 0]),
            np.r_[0, 0, lift],
            _hull(T1),
            _stance(step, 0),
        ),
        _Phase(
            1,
            T1,
            T2,
            zero,
            np.r_[lift, land],
            _points(np.array([0, turn, T2]), T2),
            _stance(step, 1),
        ),
        _Phase(
            2,
            T1 + T2,
            T3,
            zero,
            np.r_[land, 0, 0],
            _points(np.array([0, T3]), T3),
            _stance(step, 2),
        ),
    )


def _replan_phases(step: Step, elapsed: float, s: float, v: float) -> tuple[_Phase, ...]:
    """The rest of the swing at a constant alpha from (s, s') and the post-swing Hermite piece
    to the goal at rest, with x = alpha: two time functions each, so Bezier-hull checks."""
    T1, T2, T3 = step.durations
    rest = T2 - elapsed
    coast = np.array([s + v * rest, v])  # the swing's end at alpha = 0, and per unit alpha:
    push = np.array([rest * rest / 2, rest])
    return (
        _Phase(
            1,
            T1 + elapsed,
            rest,
            np.r_[s, v, coast],
            np.r_[0, 0, push],
            _hull(rest),
            _stance(step, 1),
        ),
        _Phase(2, T1 + T2, T3, np.r_[coast, 0, 0], np.r_[push, 0, 0], _hull(T3), _stance(step, 2)),
    )


def _power(T: float) -> Array:
    """(4, 4): Hermite data (s0, v0, s1, v1) to power coefficients of s(tau) on [0, T]."""
    return np.array(
        [
            [1, 0, 0, 0],
            [0, 1, 0, 0],
            [-3 / T**2, -2 / T, 3 / T**2, -1 / T],
            [2 / T**3, 1 / T**2, -2 / T**3, 1 / T**2],
        ]
    )


def _solve(step: Step, direction: Array, phases: tuple[_Phase, ...]) -> ComPlan:
    """The feasible x nearest zero, as a plan; InfeasibleStepError when there is none."""
    interval = _interval(step, direction, phases)
    if interval.empty:
        raise InfeasibleStepError(interval)
    x = min(max(0.0, interval.lower), interval.upper)
    return ComPlan(
        step=step,
        direction=direction,
        x=x,
        interval=interval,
        phases=tuple(PHASES[ph.index] for ph in phases),
        starts=np.array([ph.start for ph in phases]),
        end=sum(step.durations),
        coefficients=np.array([_power(ph.duration) @ (ph.E0 + x * ph.E1) for ph in phases]),
        maps=np.array([ph.stance.map for ph in phases]),
        shifts=np.array([ph.stance.shift for ph in phases]),
        offsets=np.array([ph.stance.offset for ph in phases]),
    )


def feasible_interval(step: Step) -> Interval:
    """The betas for which the step's plan keeps every holding foot in its cone (empty: none)."""
    return _interval(step, step.direction, _plan_phases(step))


def plan_step(step: Step) -> ComPlan:
    """The step's CoM plan with the least |beta| that holds every foot (InfeasibleStepError
    if none)."""
    return _solve(step, step.direction, _plan_phases(step))


def replan_swing(
    step: Step, direction: Array, elapsed: float, position: Array, velocity: Array
) -> ComPlan:
    """Re-plan ``elapsed`` s into the swing from the CoM's ``position`` and ``velocity``, for
    ``step``'s (new) mu and F_adh: the least |alpha| that holds every foot over the rest of the
    step (InfeasibleStepError if none). The line stays the plan's (``direction``, through the goal):
    the state's parts across it are dropped, nil when it is the plan's own state."""
    if not 0 <= elapsed < step.durations[1]:
        raise ValueError(f"{elapsed} s is not within the swing's {step.durations[1]} s")
    d = np.asarray(direction, float)
    s = float(np.dot(np.asarray(position, float) - step.goal, d))
    return _solve(step, d, _replan_phases(step, elapsed, s, float(np.dot(velocity, d))))
