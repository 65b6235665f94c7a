"""The climbing robot's solver loop: what changes between two steps (docs/climb.md).

Before each step it updates the four pads (:class:`ftfof.sim.padstate.PadTracker`); presses the
landed foot to the pre-pressure a through its landing hold and releases that press over the
body's advance that follows (:mod:`ftfof.climb.press`); sets the joint targets from the gait
through each leg's inverse kinematics against the body's plan (:mod:`ftfof.climb.targets`);
with a ``climb.controller``, adds the stance feet's force control to the servos at its control
rate and tracks the body plan that control hands it (:mod:`ftfof.climb.control_step`). After
each step it records the channels at the record rate (:mod:`ftfof.climb.recorder`) and stops the
run cleanly when the robot falls: a stance pad fully let go, or the body ``climb.fall_distance``
off its plan (:mod:`ftfof.climb.watchdog`).
"""

from __future__ import annotations

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.replan import BodyPlan
from ftfof.climb.control_step import Controller, ControlStep
from ftfof.climb.gait import LEGS
from ftfof.climb.model import BASE, Climber
from ftfof.climb.press import LandingPress, press_stiffness
from ftfof.climb.recorder import Recorder, channel_slices
from ftfof.climb.sensing import Handles, SlipMeter
from ftfof.climb.targets import JointTargets
from ftfof.climb.watchdog import Fall, Watchdog
from ftfof.sim.padstate import PadTracker

Array = NDArray[np.float64]
__all__ = ["ClimbLoop", "channel_slices"]  # the climb splits the recorder's rows by channel


class ClimbLoop:
    """The pre- and post-step functions of one climb: its parts, composed over the gait."""

    def __init__(
        self,
        robot: Climber,
        solver: exu.MainSolverImplicitSecondOrder,
        rate: float,
        control: Controller | None = None,
    ):
        spec = robot.spec
        self.r, self.solver, self.mbs = robot, solver, robot.mbs
        self.data = robot.mbs.systemData
        stop = spec.robot.platform.film.stop_radius
        self.pads = [
            PadTracker(robot.mbs, parts, robot.law, robot.initial_pressure, stop)
            for parts in robot.pads
        ]
        self.handles = Handles.of(robot, self.pads)
        slip = SlipMeter(self.handles)
        self.press = LandingPress(
            robot.gait,
            spec.platform.sensor,
            self.handles.patches,
            spec.robot.pre_pressure,
            press_stiffness(robot),
        )
        self.targets = JointTargets(robot)
        self.recorder = Recorder(robot, self.handles, self.pads, rate, slip)
        self.watchdog = Watchdog(spec.climb, robot.gait.start, self.handles.tree)
        self.control = (
            None
            if control is None
            else ControlStep(control, self.handles, slip, self.recorder.forces)
        )
        self.kp, self.kd = spec.robot.platform.joint_gains
        self.feedforward = np.zeros_like(self.targets.offsets)  # the control's torques
        self.plan: BodyPlan = robot.gait.body  # the control's re-planner may replace it
        self.held = np.ones(LEGS, dtype=bool)  # each pad bonded, as of the last step

    def __call__(self, mbs, t: float) -> bool:
        """The pre-step function: pads, press, joint targets, control; False stops the run."""
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        h = self.solver.it.currentStepSize
        _, tau, swing = self.r.gait.phase(t)
        switch = self.r.switch
        if switch is not None and not switch.done and t >= switch.switch.time:
            switch.apply(self.mbs, self.pads[switch.switch.leg])
        held = np.zeros(LEGS, dtype=bool)
        for leg, pad in enumerate(self.pads):
            held[leg] = pad.update(q, qd, h, t).bonded > 0
        self.held = held
        if swing >= 0:
            self.press.step(swing, tau, q, qd, h)
        self._servo(t, tau, swing, q, qd)
        if self.control is not None and self.control.due(t):
            self._control(t, q, qd, self._stance(self._landing(tau, swing)))
        return self.watchdog.step(t, q)

    def after_step(self, mbs, t: float) -> bool:
        """The post-step function: record the solved state at ``t``, stop on a fall."""
        if not self.recorder.due(t):
            return True
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        qdd = self.data.GetODE2Coordinates_tt(copy=False)
        _, tau, swing = self.r.gait.phase(t)
        landing = self._landing(tau, swing)
        state = (q, qd, qdd)
        self.recorder.record(t, state, swing, self._stance(landing), self.plan, self._torque(q, qd))
        return not self.watchdog.fell(t, q, self.held, landing, self.plan)

    @property
    def rows(self) -> Array:
        """The record buffer (its first ``count`` rows recorded; :func:`channel_slices`)."""
        return self.recorder.rows

    @property
    def count(self) -> int:
        return self.recorder.count

    @property
    def steps(self) -> int:
        """Solver steps taken."""
        return self.watchdog.steps

    @property
    def fall(self) -> Fall | None:
        return self.watchdog.fall

    @property
    def stopped(self) -> str:
        """Why a check stopped the run ("" if none did)."""
        return self.watchdog.stopped

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

    def _servo(self, t: float, tau: float, swing: int, q: Array, qd: Array) -> None:
        """Hand the servos their joint targets (kept where a foot is out of reach)."""
        anchored = None if self.control is None else self.control.anchored
        body = (q[self.handles.tree], qd[self.handles.tree])
        press = self.press.applied(tau, swing)
        if self.targets.update(t, (tau, swing), body, self.plan, press, anchored):
            setp = self.mbs.SetObjectParameter
            setp(self.r.tree, "jointPositionOffsetVector", self.targets.offsets.tolist())
            setp(self.r.tree, "jointVelocityOffsetVector", self.targets.rates.tolist())

    def _control(self, t: float, q: Array, qd: Array, stance: Array) -> None:
        """One control step: the stance feet's forces, as the servos' feed-forward torques."""
        assert self.control is not None
        torques, plan = self.control.step(t, q, qd, self.plan, stance)
        if plan is not None:
            self.plan = plan
        self.feedforward[BASE:] = torques.ravel()
        self.mbs.SetObjectParameter(self.r.tree, "jointForceVector", self.feedforward.tolist())

    def _torque(self, q: Array, qd: Array) -> Array:
        """The servos' torques now: the joint PD on their targets plus the control's."""
        joints = self.handles.joints
        return (
            self.kp * (self.targets.offsets[BASE:] - q[joints])
            + self.kd * (self.targets.rates[BASE:] - qd[joints])
            + self.feedforward[BASE:]
        )
