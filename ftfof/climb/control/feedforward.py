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
wrench's moment leaves them out. Controllers:

- ``none``: the QP at the nominal weights and the nominal pads;
- ``weights``: a stance foot detected slipping (:class:`~ftfof.climb.control.slip.SlipDetector`)
  gets its weights adapted by its slip rate (climbing_slip §5), the rate held at its highest
  until the stance changes (§6.3: the paper's weights start anew with each phase), and is
  anchored (:attr:`FeedForward.anchored`) until it lifts;
- ``replan``: a foot detected slipping has its pad estimated from its last ESTIMATE_SAMPLES force
  samples; the estimate replaces the nominal pad in the QP, and goes to the re-planner
  (:mod:`ftfof.climb.control.replan`), whose plan the loop then tracks;
- ``both``: the two together.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import astuple, dataclass, field

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.forces import ForceDistributor, Stance, wrench_map
from ftfof.climb.control.replan import BodyPlan, Replanner, ReplanRequest
from ftfof.climb.control.slip import (
    SlipDetector,
    adapt_weights,
    estimate_adhesion,
    estimate_pad,
    slip_rate,
)
from ftfof.climb.legs import SagittalChain
from ftfof.config import GRAVITY
from ftfof.identify.estimate import Estimate

Array = NDArray[np.float64]
CONTROL_RATE_HZ = 1000.0
NOMINAL_WEIGHTS = (1.0, 1e-3)  # tangential, normal: the normal far below (climbing_slip §5.2)
SLIP_SPAN = 0.02  # m/s: the slip rate's scale above the threshold (slip_rate)
BODY_BANDWIDTH_HZ = 5.0  # the trunk wrench's PD, critically damped
ESTIMATE_SAMPLES = 15  # force samples per estimate (the Kalman estimator's window)
FORCE_TIME_CONSTANT = 0.02  # s: the force trim's integral action on the pads' measured forces
MAX_TRIM = 5.0  # N per force component: the trim's bound (a peeling pad must not wind it up)

# a foot's last ESTIMATE_SAMPLES forces on it (f_n, f_t), or None while there are fewer
ForceWindow = Callable[[int], tuple[Array, Array] | None]


@dataclass(frozen=True)
class Pads:
    """Each foot's pad as the controller believes it."""

    friction: Array  # (4,) mu
    adhesion: Array  # (4,) F_adh, N: the shear capacity seen as normal load
    pull_off: Array  # (4,) the most each pad holds pulled normal to the wall, N


@dataclass
class Counts:
    """What the controller did over a climb (the climb's JSON reports it)."""

    solves: int = 0
    failed: int = 0  # steps whose QP found no answer: no feed-forward for them
    slips: int = 0  # slips declared (a foot's rising edge)
    estimates: int = 0  # pads re-estimated
    replans: int = 0  # new plans the re-planner gave


@dataclass
class FeedForward:
    """The controller of one climb; :meth:`step` returns the servos' feed-forward torques."""

    mode: str  # none | weights | replan | both
    chain: SagittalChain
    mass: float  # the whole robot's, kg
    inertia: float  # the trunk's pitch inertia, kg m^2
    com_height: float  # the trunk's CoM above the wall at z = 0, m
    pads: Pads
    replanner: Replanner
    detector: SlipDetector  # climb.slip_threshold and climb.slip_hold
    distributor: ForceDistributor = field(default_factory=ForceDistributor)
    counts: Counts = field(default_factory=Counts)

    def __post_init__(self) -> None:
        self.weights = np.tile(NOMINAL_WEIGHTS, (len(self.pads.friction), 1))
        self.believed = Pads(*(np.array(a, dtype=float) for a in astuple(self.pads)))
        self.trim = np.zeros((len(self.pads.friction), 2))
        self.held_rate = np.zeros(len(self.pads.friction))  # each foot's slip rate held this phase
        self.phase = np.zeros(len(self.pads.friction), dtype=bool)  # the stance it belongs to
        # The feet whose servos hold them where they are on the wall, whatever the body does
        # (the loop moves their targets with the body's error from its plan,
        # :class:`~ftfof.climb.targets.Anchors`): a slipping foot under weight adaptation, from
        # its slip until it lifts. On position servos the joint PD, not the QP, sets most of a
        # stance foot's tangential force: it holds the foot on the body, so a pad that cannot
        # carry its share slides with the body's sag on the other feet's films (the slip
        # scenario under `none`: HR's pad 4.5 mm down as the body fell 4.8 mm behind its plan),
        # and lower QP weights alone changed little (docs/decisions/0023-anchored-slipping-foot.md).
        self.anchored = np.zeros(len(self.pads.friction), dtype=bool)

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
        weights = self.weights
        if self.mode in ("weights", "both"):
            weights = adapt_weights(weights, self._hold_rate(slip_velocity, slipping, stance))
            self.anchored = (self.anchored | slipping) & stance
        new_plan = None
        if self.mode in ("replan", "both"):
            for foot in np.flatnonzero(slipping & ~was):
                new_plan = self._replan(t, int(foot), forces, stance, feet, body, body_rate, plan)
                plan = new_plan or plan
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

    def _hold_rate(self, slip_velocity: Array, slipping: Array, stance: Array) -> Array:
        """Each foot's slip rate, held at its highest since the stance last changed: the
        paper's weights stay adapted through the phase once a slip has stopped, and start anew
        with each phase (climbing_slip §6.3: the weight-only controller slips again at the next
        phase for that reason)."""
        stance = np.asarray(stance, dtype=bool)
        if not np.array_equal(stance, self.phase):
            self.held_rate = np.zeros_like(self.held_rate)
            self.phase = stance.copy()
        rate = slip_rate(slip_velocity, self.detector.threshold, SLIP_SPAN) * slipping
        self.held_rate = np.maximum(self.held_rate, rate)
        return self.held_rate

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

    def _replan(
        self,
        t: float,
        foot: int,
        forces: ForceWindow,
        stance: Array,
        feet: Array,
        body: Array,
        body_rate: Array,
        plan: BodyPlan,
    ) -> BodyPlan | None:
        """Estimate the slipping foot's pad from its last forces, believe it, and ask for a
        plan (an estimate that stays off the physical range is not believed)."""
        window = forces(foot)
        if window is None:
            return None
        got = self._estimate(foot, *window)
        if got is None:
            return None
        pads = self.believed
        pads.pull_off[foot] *= got.adhesion / pads.adhesion[foot]  # both s x strength x area
        pads.friction[foot], pads.adhesion[foot] = got.mu, got.adhesion
        self.counts.estimates += 1
        request = ReplanRequest(
            t,
            foot,
            self.believed.friction.copy(),
            self.believed.adhesion.copy(),
            stance.copy(),
            feet.copy(),
            body.copy(),
            body_rate.copy(),
            plan,
            self.believed.pull_off.copy(),
        )
        new = self.replanner(request)
        self.counts.replans += new is not None
        return new

    def _estimate(self, foot: int, fn: Array, ft: Array) -> Estimate | None:
        """The pad's (mu, F_adh) from a window of its forces. Where the two-parameter fit gives
        mu <= 0 or F_adh <= 0, the pad is losing its bonds as it slides (a peel under shear, not a
        slide on a fixed cone); its mu stays believed and only its F_adh, what it still holds, is
        fitted.
        None if even that is off the range (F_adh not finite, or <= 0)."""
        mu = float(self.believed.friction[foot])
        got = estimate_pad(fn, ft, prior=Estimate(mu, float(self.believed.adhesion[foot])))
        if math.isfinite(got.mu) and math.isfinite(got.adhesion) and got.mu > 0 < got.adhesion:
            return got
        adhesion = estimate_adhesion(fn, ft, mu)
        return Estimate(mu, adhesion) if math.isfinite(adhesion) and adhesion > 0 else None
