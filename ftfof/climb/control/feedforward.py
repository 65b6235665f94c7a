"""The stance feet's force control in the climb: the contact-force QP's torques as a feed-forward
on the joint PD (``climb.controller``, docs/climb.md "Slip").

Each control step (CONTROL_RATE_HZ, the force sensor's rate; the torques hold in between):

1. the stance feet: on the wall, and not the leg in its swing or landing hold (that one's press
   is the press loop's);
2. each foot's :class:`~ftfof.climb.control.forces.Stance`: its pad's offset from the CoM, its
   leg's Jacobian turned by the trunk's pitch into the wall frame, its pad's mu and F_adh, its
   servo limits and its QP weights;
3. the trunk wrench: the robot's weight carried up the wall, plus a PD on the body's error from
   its plan (x) and from the wall's plane (z, pitch);
4. the QP's forces plus each foot's force trim, and their torques -J^T f as the servos'
   feed-forward. The trim integrates what the pad's sensor misses of the QP's force: the joint
   PD holds its targets and the pad and film give under the foot about as much as the leg, so
   -J^T f alone got about half of f to the wall (issue 40).

The CoM is the trunk's: the legs are a quarter of the mass and sit about the hips, so the
wrench's moment leaves them out. What a slip changes is the controller's two parts, composed by
name in :mod:`ftfof.climb.control.controllers`: its adaptation (the QP weights, and the feet it
anchors, :attr:`FeedForward.anchored`) and its re-planning (the pads it believes, and the plan).
"""

from __future__ import annotations

import math
from dataclasses import astuple, dataclass, field

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.adaptation import Adaptation
from ftfof.climb.control.forces import ForceDistributor, Stance, wrench_map
from ftfof.climb.control.replan import BodyPlan
from ftfof.climb.control.replanning import Replanning, believable
from ftfof.climb.control.slip import SlipDetector, fit_pad
from ftfof.climb.control.state import Counts, ForceWindow, Pads, Sensed, SlipEstimate
from ftfof.climb.legs import SagittalChain
from ftfof.config import GRAVITY
from ftfof.identify.estimate import Estimate

Array = NDArray[np.float64]
CONTROL_RATE_HZ = 1000.0
NOMINAL_WEIGHTS = (1.0, 1e-3)  # tangential, normal: the normal far below (climbing_slip §5.2)
BODY_BANDWIDTH_HZ = 5.0  # the trunk wrench's PD, critically damped
ESTIMATE_SAMPLES = 15  # force samples per estimate (the Kalman estimator's window)
FORCE_TIME_CONSTANT = 0.02  # s: the force trim's integral action on the pads' measured forces
MAX_TRIM = 5.0  # N per force component: the trim's bound (a peeling pad must not wind it up)


@dataclass
class FeedForward:
    """The controller of one climb, its adaptation and re-planning composed by name
    (:func:`~ftfof.climb.control.controllers.compose`); :meth:`step` returns the servos'
    feed-forward torques."""

    chain: SagittalChain
    mass: float  # the whole robot's, kg
    inertia: float  # the trunk's pitch inertia, kg m^2
    com_height: float  # the trunk's CoM above the wall at z = 0, m
    pads: Pads
    detector: SlipDetector  # climb.slip_threshold and climb.slip_hold
    adaptation: Adaptation
    replanning: Replanning
    distributor: ForceDistributor = field(default_factory=ForceDistributor)
    counts: Counts = field(default_factory=Counts)
    estimates: list[SlipEstimate] = field(default_factory=list)  # every slip's, in order

    def __post_init__(self) -> None:
        self.weights = np.tile(NOMINAL_WEIGHTS, (len(self.pads.friction), 1))
        self.believed = Pads(*(np.array(a, dtype=float) for a in astuple(self.pads)))
        self.trim = np.zeros((len(self.pads.friction), 2))

    @property
    def anchored(self) -> NDArray[np.bool_]:
        """The feet the loop holds where they are on the wall: the adaptation's."""
        return self.adaptation.anchored

    def step(
        self,
        t: float,
        body: Array,
        body_rate: Array,
        plan: BodyPlan,
        theta: Array,
        feet: Array,
        stance: Array,
        slip_velocity: Array,
        forces: ForceWindow,
    ) -> tuple[Array, BodyPlan | None]:
        """(4, 3) feed-forward torques (zero for the feet off the stance, and for all if the QP
        fails), and a new body plan where a slip made the re-planner give one."""
        dt = 1.0 / CONTROL_RATE_HZ
        was = self.detector.slipping.copy()
        slipping = self.detector.update(slip_velocity, stance, dt)
        self.counts.slips += int(np.count_nonzero(slipping & ~was))
        threshold = self.detector.threshold
        weights = self.adaptation.weights(self.weights, slip_velocity, slipping, stance, threshold)
        now = Sensed(t, body, body_rate, plan, stance, feet, forces)
        estimated = self._estimate(now, np.flatnonzero(slipping & ~was))
        plan, new_plan = self.replanning.replan(now, estimated, self.believed, self.counts)
        out = np.zeros((len(stance), 3))
        on = np.flatnonzero(stance)
        wrench = self._wrench(t, body, body_rate, plan) - self._others(stance, body, feet, forces)
        qp = self._stance(on, body, theta, feet, weights)
        result = self.distributor.solve(qp, wrench)
        self.counts.solves += 1
        if not result.solved:
            self.counts.failed += 1
            return out, new_plan
        force = result.forces + self._trim(on, result.forces, forces, dt)
        out[on] = -np.einsum("nij,ni->nj", qp.jacobian, force)
        return out, new_plan

    def _estimate(self, now: Sensed, slipped: NDArray[np.int64]) -> dict[int, Estimate]:
        """Each foot that started to slip: its pad fitted from its last force samples, recorded
        in :attr:`estimates` (the climb reports them against the pad's truth), and as the cone
        would take it where that is believable (:func:`believable`). Every controller estimates;
        only a re-planning one believes, so for the others the fit is a record and changes no
        force (one Kalman update of ESTIMATE_SAMPLES samples per slip)."""
        out = {}
        for foot in map(int, slipped):
            window = now.forces(foot)
            if window is None:
                continue
            believed = self.believed
            prior = Estimate(float(believed.friction[foot]), float(believed.adhesion[foot]))
            fit = fit_pad(*window, prior=prior)
            self.estimates.append(SlipEstimate(now.time, foot, fit))
            got = believable(self.believed, foot, fit, *window)
            if got is not None:
                out[foot] = got
        return out

    def _trim(self, on: Array, wanted: Array, forces: ForceWindow, dt: float) -> Array:
        """The stance feet's force trims, integrating what the pads miss of the QP's forces.
        The servos' PD holds the joints on their targets, and the pad and film give under the
        foot about as much as the leg does, so -J^T f alone gets about half of f to the wall.
        A foot off the stance, or without a sensor window yet, starts again from zero."""
        trim = np.zeros_like(self.trim)
        for k, foot in enumerate(on):
            window = forces(int(foot))
            if window is None:
                continue
            measured = np.array([window[1][-1], window[0][-1]])
            step = (wanted[k] - measured) * dt / FORCE_TIME_CONSTANT
            trim[foot] = np.clip(self.trim[foot] + step, -MAX_TRIM, MAX_TRIM)
        self.trim = trim
        return trim[on]

    def _others(self, stance: Array, body: Array, feet: Array, forces: ForceWindow) -> Array:
        """The trunk wrench of the feet off the stance, as their pads measure it: the landing
        foot's press in its hold, which the stance must balance (0 for a foot off the wall).
        Left out, the QP asked the stance for forces the press made statically impossible, and
        the force trim pulled against it (FR moved to painted_wall at 7 s: FR slid 1.5 mm at
        FL's landing at 10 s, 0.7 mm without the trim)."""
        off = np.flatnonzero(~np.asarray(stance, dtype=bool))
        measured = [forces(int(foot)) for foot in off]
        have = [k for k, window in enumerate(measured) if window is not None]
        if not have:
            return np.zeros(3)
        f = np.array([[measured[k][1][-1], measured[k][0][-1]] for k in have])
        return wrench_map(self._offsets(off[have], body, feet)) @ f.ravel()

    def _offsets(self, which: Array, body: Array, feet: Array) -> Array:
        """(n, 2) the feet ``which``'s contact points minus the trunk's CoM, wall frame."""
        height = np.full(len(which), -self.com_height - body[1])
        return np.stack([feet[which] - body[0], height], axis=1)

    def _stance(self, on: Array, body: Array, theta: Array, feet: Array, weights: Array) -> Stance:
        c, s = math.cos(body[2]), math.sin(body[2])
        turn = np.array([[c, -s], [s, c]])  # trunk frame -> wall frame
        return Stance(
            offset=self._offsets(on, body, feet),
            jacobian=turn @ self.chain.leg.jacobian(theta[on]),
            friction=self.believed.friction[on],
            adhesion=self.believed.adhesion[on],
            torque_limit=np.tile(self.chain.torque_limits, (len(on), 1)),
            weight=weights[on],
            pull_off=self.believed.pull_off[on],
        )

    def _wrench(self, t: float, body: Array, body_rate: Array, plan: BodyPlan) -> Array:
        """The weight up the wall, and a critically damped PD toward the plan: x on the plan,
        z on the wall's plane (0), pitch level."""
        x, v = plan(np.array([t]))
        w = 2 * math.pi * BODY_BANDWIDTH_HZ
        target = np.array([x[0], 0.0, 0.0])
        rate = np.array([v[0], 0.0, 0.0])
        pd = w * w * (target - body) + 2 * w * (rate - body_rate)
        return np.array([self.mass * GRAVITY, 0.0, 0.0]) + pd * np.array(
            [self.mass, self.mass, self.inertia]
        )
