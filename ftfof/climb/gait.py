"""The crawl up the wall: when each leg swings, where each foot is, where the body should be.

One step is one leg's swing along the trajectory under test (T3, the body still, so the foot's
path in the body frame is the path on the wall, as on the platform), its landing hold (the
platform's ``landing_hold``), then the body's advance by a quarter stride with all four feet
holding (``climb.shift_time``, minimum jerk). After four steps every foot has moved one stride,
the trajectory's P15 - P0, and so has the body. Before the first step the robot settles and
presses every pad to the pre-pressure a, as the platform does.

A trajectory that ends below the wall (MST-Q's P15z < 0: its support rack keeps pressing) leaves
that foot pressed through its landing hold; it returns to the wall's surface during the next
advance, so the next swing starts where the trajectory does, at P0.

World frame: x up the wall from the body's start, z out of the wall; pure numpy, vectorised over
time.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from ftfof.demand import LEGS
from ftfof.trajectory.blend import min_jerk
from ftfof.trajectory.piecewise import PiecewiseQuintic

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Gait:
    """A crawl of ``steps`` swings of ``trajectory`` in ``order``, starting at ``start``."""

    trajectory: PiecewiseQuintic  # the swing, P0 = (0, 0), over [0, T3]
    order: tuple[int, ...]  # leg per step, cycled
    steps: int
    start: float  # s, first lift-off (after settling and pressing)
    hold: float  # s, landing hold
    shift: float  # s, body advance
    hips: Array  # (4,) hip x on the body, m
    foot_start: Array  # (2,) every foot's start P0 relative to its hip (the chain's -hip)

    @cached_property
    def stride(self) -> Array:
        """P15 - P0 of the swing, m."""
        return self.trajectory.sample(np.array([self.trajectory.duration])).position[0, 0]

    @cached_property
    def advance(self) -> float:
        """The body's advance per step: a quarter stride."""
        return float(self.stride[0]) / LEGS

    @property
    def swing(self) -> float:
        return self.trajectory.duration

    @property
    def period(self) -> float:
        return self.swing + self.hold + self.shift

    @property
    def end(self) -> float:
        return self.start + self.steps * self.period

    def leg_of(self, step: int) -> int:
        return self.order[step % len(self.order)]

    def lift_off(self, step: int) -> float:
        """When step ``step``'s swing starts."""
        return self.start + step * self.period

    def step_at(self, t: Array) -> Array:
        """The step each time falls in (-1 before the first; the last after the end)."""
        k = np.floor((np.asarray(t, float) - self.start) / self.period).astype(int)
        return np.where(np.asarray(t) < self.start, -1, np.minimum(k, self.steps - 1))

    def phase(self, t: float) -> tuple[int, float, int]:
        """At one time: its step (-1 before the first), the time since that step's lift-off,
        and the step's leg (-1 before the first)."""
        step = int(self.step_at(np.array([t]))[0])
        if step < 0:
            return -1, t - self.start, -1
        return step, t - self.lift_off(step), self.leg_of(step)

    def body(self, t: Array) -> tuple[Array, Array]:
        """The planned body x and its rate at ``t``: one quarter stride per completed advance."""
        t = np.asarray(t, dtype=float)
        into = t - (self.start + self.swing + self.hold)  # time since the first advance began
        k = np.floor(into / self.period)
        s = (into - k * self.period) / self.shift
        blend, rate = min_jerk(s)
        within = (k >= 0) & (k < self.steps)
        x = np.where(within, k + blend, np.where(k >= self.steps, self.steps, 0.0))
        moving = within & (s > 0) & (s < 1)
        return self.advance * x, np.where(moving, self.advance * rate / self.shift, 0.0)

    def initial_feet(self) -> Array:
        """(4,) each foot's x at t = 0: the j-th to swing is j quarter strides into its stroke."""
        x = np.empty(LEGS)
        for j in range(LEGS):
            leg = self.order[j]
            x[leg] = self.hips[leg] + self.foot_start[0] + j * self.advance
        return x

    def feet(self, t: float) -> tuple[Array, Array]:
        """(4, 2) foot targets on the wall at ``t`` and their rates (scalar time: the solver's)."""
        pos = np.zeros((LEGS, 2))
        vel = np.zeros((LEGS, 2))
        pos[:, 0] = self.initial_feet()
        stride = self.stride
        k = int(self.step_at(np.array([t]))[0])
        for step in range(max(k, 0)):  # swings done before this step
            pos[self.leg_of(step), 0] += stride[0]
        if k < 0:
            return pos, vel
        leg = self.leg_of(k)
        tau = t - self.lift_off(k)
        if tau <= self.swing + self.hold:
            s = self.trajectory.sample(np.array([tau]))
            pos[leg] += s.position[0, 0]
            vel[leg] = s.velocity[0, 0]
            return pos, vel
        pos[leg, 0] += stride[0]
        if stride[1] != 0.0:  # the pressed landing returns to the wall during the advance
            blend, rate = min_jerk(np.array((tau - self.swing - self.hold) / self.shift))
            pos[leg, 1] = stride[1] * (1 - float(blend))
            vel[leg, 1] = -stride[1] * float(rate) / self.shift
        return pos, vel
