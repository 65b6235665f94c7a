"""The climbing robot's solver loop: what changes between two steps (docs/climb.md).

Before each step it updates the four pads (:class:`ftfof.sim.padstate.PadTracker`); presses the
landed foot to the pre-pressure a through its landing hold (the platform's integral loop on the
wall patch's normal force) and releases that press
over the body's advance that follows; sets
the joint targets from the gait through each leg's inverse kinematics against the body's plan;
records the channels at the record rate; and stops the run cleanly when the robot falls: a
stance pad fully let go, or the body ``climb.fall_distance`` off its plan. With a
``climb.controller``, it adds the stance feet's force control to the servos at its control rate
(:mod:`ftfof.climb.control.feedforward`) and tracks the body plan that control hands it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.feedforward import CONTROL_RATE_HZ, ESTIMATE_SAMPLES, FeedForward
from ftfof.climb.control.replan import BodyPlan
from ftfof.climb.gait import LEGS, min_jerk
from ftfof.climb.model import BASE, JOINTS, Climber
from ftfof.config import LEG_NAMES
from ftfof.sim import film
from ftfof.sim.foot import backing_stiffness, pressed_area
from ftfof.sim.padstate import PadTracker
from ftfof.sim.prestep import PRESS_TIME_CONSTANT

Array = NDArray[np.float64]
CHANNELS = (
    ("t", 1),
    ("body", 3),  # x, z, pitch
    ("body_rate", 3),
    ("body_acc", 3),
    ("body_plan", 1),
    ("foot", 2 * LEGS),  # x, z per leg
    ("force", 2 * LEGS),  # Fx, Fz of each pad on the wall (tension positive)
    ("bonds", LEGS),
    ("lowest", LEGS),  # the film's lowest point above its wall patch
    ("curvature", LEGS),  # free-span curvature of each swinging pad's film (0 in stance)
    ("joints", JOINTS * LEGS),  # chain angles relative to the trunk
    ("torque", JOINTS * LEGS),
    ("swing", 1),  # the leg whose step it is (swing, landing hold, advance), -1 before the first
    ("slip_velocity", LEGS),  # each stance pad's rate along its patch over the record, m/s
)


@dataclass
class Fall:
    time: float
    why: str


class ClimbLoop:
    """Per-climb state shared by the pre-step function."""

    def __init__(
        self,
        robot: Climber,
        solver: exu.MainSolverImplicitSecondOrder,
        rate: float,
        control: FeedForward | None = None,
    ):
        spec = robot.spec
        self.r, self.solver = robot, solver
        self.mbs = robot.mbs
        self.data = robot.mbs.systemData
        stop = spec.robot.platform.film.stop_radius
        self.pads = [
            PadTracker(robot.mbs, parts, robot.law, robot.initial_pressure, stop)
            for parts in robot.pads
        ]
        self.tree = int(robot.mbs.GetNodeODE2Index(robot.tree_node))
        self.feet = np.array([robot.mbs.GetNodeODE2Index(f) for f in robot.feet], np.int64)
        self.patches = np.array([p.plate_index for p in self.pads], np.int64)
        ref = np.array([robot.mbs.GetNodeOutput(f, exu.OutputVariableType.Position,
                                                exu.ConfigurationType.Reference)[:2]
                        for f in robot.feet])  # fmt: skip
        self.foot_ref = ref
        self.node_index = [p.node_index for p in self.pads]
        self.press_depth = np.zeros(LEGS)
        self.series_stiffness = _series_stiffness(robot)
        kp, kd = spec.robot.platform.joint_gains
        self.kp, self.kd = kp, kd
        self.offsets = robot.q0.copy()
        self.rates = np.zeros_like(self.offsets)
        self.sensor = spec.platform.sensor
        self.every = 1.0 / rate
        self.next_record = 0.0
        n = math.ceil(robot.gait.end * rate) + 8
        self.width = sum(w for _, w in CHANNELS)
        self.rows = np.full((n, self.width), np.nan)
        self.count = 0
        self.fall: Fall | None = None
        self.fall_distance = spec.climb.fall_distance
        self.deadline = time.perf_counter() + spec.climb.time_budget
        self.stopped = ""
        self.steps = 0
        self.held = np.ones(LEGS, dtype=bool)
        self.control = control
        self.plan: BodyPlan = robot.gait.body  # the control's re-planner may replace it
        self.feedforward = np.zeros_like(self.offsets)
        self.next_control = 0.0
        self.force_columns = channel_slices()["force"]
        self.anchors = Anchors.none()  # the feet the controller holds on the wall, and how
        self.slip_clock: dict[str, tuple[float, Array]] = {}  # (t, film positions) per reader

    def __call__(self, mbs, t: float) -> bool:
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        h = self.solver.it.currentStepSize
        gait = self.r.gait
        _, tau, swing = gait.phase(t)
        switch = self.r.switch
        if switch is not None and not switch.done and t >= switch.switch.time:
            switch.apply(self.mbs, self.pads[switch.switch.leg])
        held = np.zeros(LEGS, dtype=bool)
        for leg, pad in enumerate(self.pads):
            step = pad.update(q, qd, h, t)
            held[leg] = step.bonded > 0
        self.held = held
        if swing >= 0:
            self._press(swing, tau, q, qd)
        self._targets(t, tau, swing, q, qd)
        if self.control is not None and t >= self.next_control - 1e-12:
            self._control(t, q, qd, tau, swing)
            self.next_control += 1.0 / CONTROL_RATE_HZ
        self.steps += 1
        if self.steps % 64 == 0:
            if not np.isfinite(q).all():
                self.stopped = f"non-finite state at t = {t:.4f} s"
                return False
            if time.perf_counter() > self.deadline:
                budget = self.r.spec.climb.time_budget
                self.stopped = f"time budget of {budget} s exceeded at t = {t:.4f} s"
                return False
        return True

    def after_step(self, mbs, t: float) -> bool:
        """The post-step function: record the solved state at ``t``, stop on a fall."""
        if t < self.next_record - 1e-9:
            return True
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        _, tau, swing = self.r.gait.phase(t)
        landing = self._landing(tau, swing)
        self._record(t, q, qd, swing, self._stance(landing))
        self.next_record += self.every
        return not self._fell(t, q, self.held, landing)

    def _landing(self, tau: float, swing: int) -> int:
        """The leg in its swing or landing hold (its pad bonds in the hold), -1 if none."""
        gait = self.r.gait
        return swing if tau < gait.swing + gait.hold else -1

    def _stance(self, landing: int) -> Array:
        """The feet holding the robot: bonded, and not the leg in its swing or landing hold."""
        stance = self.held.copy()
        if landing >= 0:
            stance[landing] = False
        return stance

    def _control(self, t: float, q: Array, qd: Array, tau: float, swing: int) -> None:
        """One control step: the stance feet's forces, as the servos' feed-forward torques."""
        assert self.control is not None
        b = self.tree
        stance = self._stance(self._landing(tau, swing))
        torques, plan = self.control.step(
            t,
            q[b : b + BASE].copy(),
            qd[b : b + BASE].copy(),
            self.plan,
            q[b + BASE : b + BASE + JOINTS * LEGS].reshape(LEGS, JOINTS),
            self.foot_ref[:, 0] + q[self.feet],
            stance,
            self._slip_velocity(q, t, stance, "control"),
            self._forces,
        )
        if plan is not None:
            self.plan = plan
        self.feedforward[BASE:] = torques.ravel()
        self.mbs.SetObjectParameter(self.r.tree, "jointForceVector", self.feedforward.tolist())

    def _slip_velocity(self, q: Array, t: float, stance: Array, clock: str) -> Array:
        """Each stance pad's velocity along its wall patch, 0 off the stance: its film nodes' mean
        position (the foot above it rocks on its ankle; the pad's nodes are what slide) since
        ``clock``'s last reading. Not the nodes' velocities: on the plate's stiff backing they
        chatter +-5 mm/s from one solver step to the next while the pad stays within 10 um, and
        the records, a step apart, read that as a steady slide."""
        position = np.array([q[idx].mean() for idx in self.node_index]) - q[self.patches]
        last_t, last = self.slip_clock.get(clock, (t, position))
        self.slip_clock[clock] = (t, position)
        rate = (position - last) / (t - last_t) if t > last_t else np.zeros(LEGS)
        return np.where(stance, rate, 0.0)

    def _forces(self, leg: int) -> tuple[Array, Array] | None:
        """The wall's force on ``leg``'s foot over the last ESTIMATE_SAMPLES records: (f_n, f_t),
        f_n > 0 pressing (the force channel is the pad's on the wall: negated)."""
        if self.count < ESTIMATE_SAMPLES:
            return None
        f = self.rows[self.count - ESTIMATE_SAMPLES : self.count, self.force_columns]
        return -f[:, 2 * leg + 1], -f[:, 2 * leg]

    def _press(self, leg: int, tau: float, q: Array, qd: Array) -> None:
        """In the landing hold, an integral loop on the leg's wall patch: it reads a.

        The robot starts with every pad bonded at the pre-pressure; on a vertical wall no
        normal force but the feet's own acts, so a foot presses only against the others' pull:
        one at a time, on landing. Each landing finds its depth afresh from zero (a depth kept
        from the last landing would jump the foot into the wall at the next lift-off)."""
        gait = self.r.gait
        if tau < gait.swing:
            self.press_depth[leg] = 0.0
            return
        if tau >= gait.swing + gait.hold:
            return
        sensor = self.sensor
        z = self.patches[leg] + 1
        compression = -(sensor.stiffness * q[z] + sensor.damping * qd[z])
        error = self.r.spec.robot.pre_pressure - compression
        h = self.solver.it.currentStepSize
        self.press_depth[leg] += error / self.series_stiffness * min(h / PRESS_TIME_CONSTANT, 1.0)

    def _applied_press(self, tau: float, leg: int) -> Array:
        """Each leg's press into the wall now: the landing leg's loop depth through its swing
        and hold, released over the advance that follows (a press held through the stance would
        make the stance feet push against each other: on a wall nothing else takes it)."""
        gait = self.r.gait
        out = np.zeros(LEGS)
        if leg < 0:
            return out
        release = (tau - gait.swing - gait.hold) / gait.shift
        out[leg] = self.press_depth[leg] * (1.0 - float(min_jerk(np.array(release))[0]))
        return out

    def _targets(self, t: float, tau: float, swing: int, q: Array, qd: Array) -> None:
        """Joint targets: each foot's gait target, relative to the hip on the body's plan; an
        anchored foot's (:class:`Anchors`) moved with the body's error from its plan, so that
        it stays where it was on the wall."""
        gait, chain = self.r.gait, self.r.chain
        feet, feet_v = gait.feet(t)
        body, body_v = self.plan(np.array([t]))
        feet[:, 1] -= self._applied_press(tau, swing)
        if self.control is not None and (self.control.anchored.any() or self.anchors.active):
            fade = np.zeros(LEGS)  # of a released foot's shift: it fades over the foot's swing
            if swing >= 0 and tau < gait.swing:
                fade[swing] = 1.0 - float(min_jerk(np.array(tau / gait.swing))[0])
            error = (q[self.tree] - body[0], qd[self.tree] - body_v[0])
            self.anchors = self.anchors.step(self.control.anchored, fade, *error)
            feet[:, 0] += self.anchors.shift
            feet_v[:, 0] += self.anchors.shift_v
        rel, rel_v = hip_frame(feet, feet_v, body[0], body_v[0], chain.hip[0], gait.hips)
        theta = chain.leg.inverse(rel)
        if not np.all(np.isfinite(theta)):
            return  # out of reach: keep the last targets (the run's checks refuse such paths)
        jac = chain.leg.jacobian(theta)  # the third joint follows -(q1 + q2): J @ [I; -1 -1]
        free = np.linalg.solve(jac[..., :2] - jac[..., 2:], rel_v[..., None])[..., 0]
        rates = chain.leg.sagittal_rates(theta, free)
        self.offsets[BASE:] = theta.ravel()
        self.rates[BASE:] = rates.ravel()
        setp = self.mbs.SetObjectParameter
        setp(self.r.tree, "jointPositionOffsetVector", self.offsets.tolist())
        setp(self.r.tree, "jointVelocityOffsetVector", self.rates.tolist())

    def _record(self, t: float, q: Array, qd: Array, swing: int, stance: Array) -> None:
        if self.count >= len(self.rows):
            return
        qdd = self.data.GetODE2Coordinates_tt(copy=False)
        b = self.tree
        joints = slice(b + BASE, b + BASE + JOINTS * LEGS)
        torque = (
            self.kp * (self.offsets[BASE:] - q[joints])
            + self.kd * (self.rates[BASE:] - qd[joints])
            + self.feedforward[BASE:]
        )
        sensor, mass = self.sensor, self.sensor.plate_mass
        px, pz = self.patches, self.patches + 1
        fx = sensor.stiffness * q[px] + sensor.damping * qd[px] + mass * qdd[px]
        fz = sensor.stiffness * q[pz] + sensor.damping * qd[pz] + mass * qdd[pz]
        foot = self.foot_ref + np.stack([q[self.feet], q[self.feet + 1]], axis=1)
        bonds = np.array([np.count_nonzero(~p.state.broken) for p in self.pads], float)
        lowest = np.array(
            [float(np.min(q[idx + 1] - q[pz[i]])) for i, idx in enumerate(self.node_index)]
        )
        curvature = np.zeros(LEGS)
        if swing >= 0:
            curvature[swing] = self._curvature(q, swing)
        plan, _ = self.plan(np.array([t]))
        slip = self._slip_velocity(q, t, stance, "record")
        self.rows[self.count] = np.concatenate(
            [
                [t],
                q[b : b + BASE],
                qd[b : b + BASE],
                qdd[b : b + BASE],
                plan,
                foot.ravel(),
                np.stack([fx, fz], axis=1).ravel(),
                bonds,
                lowest,
                curvature,
                q[joints],
                torque,
                [swing],
                slip,
            ]
        )
        self.count += 1

    def _curvature(self, q: Array, leg: int) -> float:
        """The free-span curvature of ``leg``'s film now (:mod:`ftfof.sim.film`)."""
        idx = self.node_index[leg]
        coords = q[idx[:, None] + np.arange(4)][None]
        coords = coords - np.array([0.0, q[self.patches[leg] + 1], 0.0, 0.0])
        bonded = ~self.pads[leg].state.broken[None]
        parts = self.r.pads[leg]
        return float(film.free_span_curvature(coords, parts.x_ref, self.r.clamp_edge, bonded)[0])

    def _fell(self, t: float, q: Array, held: Array, swing: int) -> bool:
        """A stance pad let go, or the body left its plan: the robot has fallen. ``swing`` is the
        leg in the air or in its landing hold (-1 after: its pad then holds the robot too)."""
        stance = np.ones(LEGS, dtype=bool)
        if swing >= 0:
            stance[swing] = False
        if t > self.r.gait.start and not held[stance].all():
            leg = int(np.flatnonzero(stance & ~held)[0])
            self.fall = Fall(t, f"the {LEG_NAMES[leg]} stance pad let go at t = {t:.3f} s")
        plan, _ = self.plan(np.array([t]))
        b = self.tree
        off = math.hypot(q[b] - plan[0], q[b + 1])
        if self.fall is None and off > self.fall_distance:
            self.fall = Fall(t, f"the body left its plan by {1e3 * off:.1f} mm at t = {t:.3f} s")
        return self.fall is not None


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


def _series_stiffness(robot: Climber) -> float:
    """Estimate of a leg's press path stiffness: joints at the foot, mount, sensor, contact."""
    spec = robot.spec
    mech = spec.robot.platform
    l1, l2 = robot.chain.links
    pad = spec.robot.foot.pad_length
    parts = [
        mech.joint_gains[0] / max(l1, l2) ** 2,
        spec.platform.sensor.stiffness,
        robot.law.contact_stiffness * pressed_area(mech.foot, mech.film, pad),
        backing_stiffness(mech.foot, pad * mech.film.width),
    ]
    mount = spec.robot.climber.foot_mount_stiffness if spec.robot.climber else None
    if mount is not None:
        parts.append(mount.z)
    return 1.0 / sum(1.0 / k for k in parts)


def channel_slices() -> dict[str, slice]:
    """Where each channel sits in a record row."""
    out, at = {}, 0
    for name, width in CHANNELS:
        out[name] = slice(at, at + width)
        at += width
    return out
