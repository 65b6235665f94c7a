"""The one-step CoM planner as the ``replan`` and ``both`` controllers' re-planner (issue 40).

The crawl's step k maps onto the planner's :class:`~ftfof.climb.control.com_step.Step` as:

- pre-swing: the previous step's body advance (every foot holds), ``gait.shift`` long;
- swing: step k's swing and landing hold (``gait.swing + gait.hold``), the stepping leg off the
  stance as the loop has it (its landing's press is the press loop's);
- post-swing: step k's body advance, ``gait.shift``, the leg at its landing;

the CoM from the plan's body x at lift-off to its x after the advance, at the trunk's height
(the controller's CoM: the trunk's, the legs left out), the feet on the wall at z = 0. A slip
declared in the swing or landing hold is re-planned with
:func:`~ftfof.climb.control.planner.replan_swing` from the plan's state at the slip, with every
pad's believed mu, F_adh and pull-off: the new plan follows the planner's CoM x (its z stays the
wall's plane, as the controller holds it) to the goal at rest, then the plan it replaces. It
starts where the plan is, not where the body is: the body's measured state follows the slide,
and a plan started from it chased the slide (HR on the dusty wall: the robot fell). A slip
outside those phases (settling, the advance), with a second foot off the wall, or with a pad
believed off the physical range (mu or F_adh not positive), is left to the plan the loop has,
as is a step the planner finds infeasible.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.com_step import Foothold, Step
from ftfof.climb.control.cones import InfeasibleStepError
from ftfof.climb.control.planner import ComPlan, replan_swing
from ftfof.climb.control.replan import BodyPlan, ReplanRequest
from ftfof.climb.gait import Gait

Array = NDArray[np.float64]
log = logging.getLogger(__name__)


@dataclass
class ReplanCounts:
    """What the re-planner answered over a climb."""

    planned: int = 0  # new plans
    infeasible: int = 0  # the planner found no CoM that holds every pad: the plan kept
    outside: int = 0  # a slip outside the phases it plans (or a second foot off): plan kept


@dataclass
class PlannerReplanner:
    """A :data:`~ftfof.climb.control.replan.Replanner` of the crawl ``gait`` for a robot of
    ``mass`` (kg) whose CoM is ``com_height`` (m) off the wall."""

    gait: Gait
    mass: float
    com_height: float
    counts: ReplanCounts = field(default_factory=ReplanCounts)

    def step_at(self, request: ReplanRequest) -> tuple[Step, float, float] | None:
        """The planner's step for the request's time, its clock's origin (s, on the climb's
        clock) and the time into its swing; None outside a swing or landing hold."""
        gait = self.gait
        k, tau, leg = gait.phase(request.time)
        off = gait.swing + gait.hold
        if k < 0 or not 0 <= tau < off:
            return None
        stance = np.asarray(request.stance, bool)
        others = np.ones(len(stance), bool)
        others[leg] = False
        pads = np.concatenate([request.friction, request.adhesion])
        if not stance[others].all() or not (np.isfinite(pads).all() and pads.min() > 0):
            return None  # a second foot off the wall, or a pad off the physical range
        lift = gait.lift_off(k)
        x = request.plan(np.array([lift, lift + off + gait.shift]))[0]
        pull = request.pull_off if request.pull_off is not None else request.adhesion
        feet = tuple(
            Foothold(
                np.array([request.feet[i], 0.0]),
                float(request.friction[i]),
                float(request.adhesion[i]),
                pull_off=float(pull[i]),
            )
            for i in range(len(stance))
        )
        landed = gait.feet(lift + off)[0][leg, 0]
        landing = Foothold(
            np.array([landed, 0.0]), feet[leg].mu, feet[leg].adhesion, pull_off=feet[leg].pull
        )
        step = Step(
            mass=self.mass,
            start=np.array([x[0], self.com_height]),
            goal=np.array([x[1], self.com_height]),
            feet=feet,
            swing=leg,
            landing=landing,
            durations=(gait.shift, off, gait.shift),
        )
        return step, lift - gait.shift, float(tau)

    def __call__(self, request: ReplanRequest) -> BodyPlan | None:
        found = self.step_at(request)
        if found is None:
            self.counts.outside += 1
            return None
        step, origin, elapsed = found
        x, v = request.plan(np.array([request.time]))
        try:
            com = replan_swing(
                step,
                np.array([1.0, 0.0]),
                elapsed,
                np.array([x[0], self.com_height]),
                np.array([v[0], 0.0]),
            )
        except InfeasibleStepError as err:
            self.counts.infeasible += 1
            log.info(
                "t = %.3f s: no re-plan after foot %d slipped: %s", request.time, request.foot, err
            )
            return None
        self.counts.planned += 1
        return followed(com, origin, request.time, request.plan)


def followed(com: ComPlan, origin: float, now: float, after: BodyPlan) -> BodyPlan:
    """The body plan that tracks ``com``'s x from ``now`` to its end (its clock starts at
    ``origin`` on the climb's) and ``after`` outside that span."""
    end = origin + com.end

    def plan(t: Array) -> tuple[Array, Array]:
        t = np.asarray(t, float)
        x, v = after(t)
        x, v = np.array(x, float, copy=True), np.array(v, float, copy=True)
        inside = (t >= now) & (t <= end)
        if inside.any():
            p, dp, _ = com.state(np.clip(t[inside] - origin, com.starts[0], com.end))
            x[inside], v[inside] = p[:, 0], dp[:, 0]
        return x, v

    return plan
