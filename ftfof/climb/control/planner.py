"""One step's CoM plan that keeps every holding pad in its adhesion-shifted friction cone
(climbing_slip §3; the re-plan after a slip, §4.2), for our sagittal robot: the method, its
parts in their modules (the step, its frame and its cones: :mod:`~ftfof.climb.control.com_step`;
the pieces and their checks: :mod:`~ftfof.climb.control.hermite`; the feasible interval:
:mod:`~ftfof.climb.control.cones`).

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
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.com_step import G, Step
from ftfof.climb.control.cones import (
    PHASES,
    InfeasibleStepError,
    Interval,
    Phase,
    interval_of,
    stance_map,
)
from ftfof.climb.control.hermite import hull, points, power

Array = NDArray[np.float64]


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


def _plan_phases(step: Step) -> tuple[Phase, ...]:
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
        Phase(
            0,
            0.0,
            T1,
            np.array([-distance, 0, 0, 0]),
            np.r_[0, 0, lift],
            hull(T1),
            stance_map(step, 0),
        ),
        Phase(
            1,
            T1,
            T2,
            zero,
            np.r_[lift, land],
            points(np.array([0, turn, T2]), T2),
            stance_map(step, 1),
        ),
        Phase(
            2,
            T1 + T2,
            T3,
            zero,
            np.r_[land, 0, 0],
            points(np.array([0, T3]), T3),
            stance_map(step, 2),
        ),
    )


def _replan_phases(step: Step, elapsed: float, s: float, v: float) -> tuple[Phase, ...]:
    """The rest of the swing at a constant alpha from (s, s') and the post-swing Hermite piece
    to the goal at rest, with x = alpha: two time functions each, so Bezier-hull checks."""
    T1, T2, T3 = step.durations
    rest = T2 - elapsed
    coast = np.array([s + v * rest, v])  # the swing's end at alpha = 0, and per unit alpha:
    push = np.array([rest * rest / 2, rest])
    return (
        Phase(
            1,
            T1 + elapsed,
            rest,
            np.r_[s, v, coast],
            np.r_[0, 0, push],
            hull(rest),
            stance_map(step, 1),
        ),
        Phase(2, T1 + T2, T3, np.r_[coast, 0, 0], np.r_[push, 0, 0], hull(T3), stance_map(step, 2)),
    )


def _solve(step: Step, direction: Array, phases: tuple[Phase, ...]) -> ComPlan:
    """The feasible x nearest zero, as a plan; InfeasibleStepError when there is none."""
    interval = interval_of(step, direction, phases)
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
        coefficients=np.array([power(ph.duration) @ (ph.E0 + x * ph.E1) for ph in phases]),
        maps=np.array([ph.stance.map for ph in phases]),
        shifts=np.array([ph.stance.shift for ph in phases]),
        offsets=np.array([ph.stance.offset for ph in phases]),
    )


def feasible_interval(step: Step) -> Interval:
    """The betas for which the step's plan keeps every holding foot in its cone (empty: none)."""
    return interval_of(step, step.direction, _plan_phases(step))


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
