"""The servos' joint targets: each foot's gait target on the wall, through its leg's inverse
kinematics relative to the hip on the body's plan.

The landed foot's target is pressed into the wall by its landing press
(:class:`ftfof.climb.press.LandingPress`). Under a controller that anchors slipping feet, an
anchored foot's target moves with the body's error from its plan (:class:`Anchors`), so that it
stays where it was on the wall.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.replan import BodyPlan
from ftfof.climb.gait import LEGS
from ftfof.climb.model import BASE, Climber
from ftfof.trajectory.blend import min_jerk

Array = NDArray[np.float64]


class JointTargets:
    """The tree's joint position and velocity offsets (the servos' targets; the floating base's
    three stay at their start) and the anchors that shift them."""

    def __init__(self, robot: Climber):
        self.gait, self.chain = robot.gait, robot.chain
        self.offsets = robot.q0.copy()
        self.rates = np.zeros_like(self.offsets)
        self.anchors = Anchors.none()  # the feet the controller holds on the wall, and how

    def update(
        self,
        t: float,
        phase: tuple[float, int],
        body: tuple[float, float],
        plan: BodyPlan,
        press: Array,
        anchored: Array | None,
    ) -> bool:
        """Set the targets at ``t``, ``phase`` (time since the step's lift-off, the leg whose
        step it is) with the trunk at ``body`` (x, its rate), tracking ``plan``, each foot
        pressed ``press`` into the wall and the controller's ``anchored`` feet (None: no
        controller). False (the last targets kept) where a foot is out of reach: the run's
        checks refuse such paths."""
        gait, chain = self.gait, self.chain
        tau, swing = phase
        feet, feet_v = gait.feet(t)
        planned, planned_v = plan(np.array([t]))
        feet[:, 1] -= press
        if anchored is not None and (anchored.any() or self.anchors.active):
            fade = np.zeros(LEGS)  # of a released foot's shift: it fades over the foot's swing
            if swing >= 0 and tau < gait.swing:
                fade[swing] = 1.0 - float(min_jerk(np.array(tau / gait.swing))[0])
            error = (body[0] - planned[0], body[1] - planned_v[0])
            self.anchors = self.anchors.step(anchored, fade, *error)
            feet[:, 0] += self.anchors.shift
            feet_v[:, 0] += self.anchors.shift_v
        rel, rel_v = hip_frame(feet, feet_v, planned[0], planned_v[0], chain.hip[0], gait.hips)
        theta = chain.leg.inverse(rel)
        if not np.all(np.isfinite(theta)):
            return False
        jac = chain.leg.jacobian(theta)  # the third joint follows -(q1 + q2): J @ [I; -1 -1]
        free = np.linalg.solve(jac[..., :2] - jac[..., 2:], rel_v[..., None])[..., 0]
        rates = chain.leg.sagittal_rates(theta, free)
        self.offsets[BASE:] = theta.ravel()
        self.rates[BASE:] = rates.ravel()
        return True


def hip_frame(
    feet: Array, feet_v: Array, body: float, body_v: float, hip: float, hips: Array
) -> tuple[Array, Array]:
    """The feet's wall targets (m, m/s; x along the wall, z off it) in each leg's trajectory
    frame, the one the servos' inverse kinematics takes: x from its hip's P0 with the body at
    ``body``, z off the wall. A servo holding these places each foot on the wall at ``rel`` +
    the body's x + ``hips`` - ``hip``: where the body really is, not where it was planned."""
    rel = feet.copy()
    rel[:, 0] += hip - body - hips
    return rel, feet_v - np.array([body_v, 0.0])


@dataclass(frozen=True)
class Anchors:
    """The feet the controller holds where they are on the wall (its ``anchored`` feet) and each
    foot's shift of its gait target along the wall. The servo places a foot relative to the
    body, so a foot lands on the wall where its target says plus the body's error from its
    plan; an anchored foot's target is shifted back by that error's change since it was
    anchored (``origin``, the error then), which keeps it where it was on the wall whatever the
    body does; the shift starts from 0. A foot released as it lifts keeps the shift it had
    (``released``), faded to 0 over its swing, so its target does not jump under the pad it is
    peeling."""

    origin: Array  # the body's error when each anchored foot was anchored (NaN: not anchored)
    released: Array  # m, a released foot's shift as it was released (0: none to fade)
    shift: Array  # m, each foot's target shift now
    shift_v: Array  # m/s

    @classmethod
    def none(cls) -> Anchors:
        return cls(np.full(LEGS, np.nan), np.zeros(LEGS), np.zeros(LEGS), np.zeros(LEGS))

    @property
    def active(self) -> bool:
        """Whether any foot is anchored or fading: if not, every shift is 0 and stays so until
        the controller anchors a foot (the loop skips the step then)."""
        return bool((~np.isnan(self.origin)).any() or self.released.any())

    def step(self, anchored: Array, fade: Array, error: float, error_v: float) -> Anchors:
        """The anchors after one step: the ``anchored`` feet now, the fraction of a released
        foot's shift left (``fade``: 1 as its swing starts, 0 from its end), the body's
        ``error`` from its plan along the wall and its rate."""
        was = ~np.isnan(self.origin)
        origin = np.where(anchored, np.where(was, self.origin, error), np.nan)
        released = np.where(was & ~anchored, self.origin - error, self.released)
        shift = np.where(anchored, origin - error, released * fade)
        released = np.where(anchored | (fade <= 0.0), 0.0, released)
        return Anchors(origin, released, shift, np.where(anchored, -error_v, 0.0))
