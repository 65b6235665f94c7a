"""The solver loop's pre-step function: everything the protocol changes between two steps.

Before each step it updates the pad (:class:`ftfof.sim.padstate.PadTracker`: bond states,
idle connectors, the film's curvature stops), holds
the press depth on the pre-pressure until the trajectory starts, throws the photoelectric switch
once the pad is off and clear, and picks the step: ``solver.step`` while bonds break or the pad
lands and ``solver.free_step`` elsewhere (the defaults are one step throughout, since a change of
step shakes the simulated body: docs/simulator.md, "Time step"). With ``solver.phase_steps`` it
takes a longer step in the protocol's phases named there (:meth:`PreStep._phase` names the phase
of a time), set after a step so that Exudyn's clock and its integration agree
(:meth:`PreStep.after_step`). A non-finite state or the time budget stops the
run, with the reason kept for the sample's record.
"""

from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.config import Sensor
from ftfof.sim.model import Platform
from ftfof.sim.padstate import PadTracker
from ftfof.sim.records import FailureReason

Array = NDArray[np.float64]
PRESS_TIME_CONSTANT = 0.01  # s, integral action of the pre-pressure loop
LANDING_WINDOW = 0.003  # m: below this lowest-film height after detachment, take small steps
PEEL_TAIL = 0.03  # s of small steps after the last bond breaks (release ringing, IMU peak)
NEAR_BREAK = 0.3  # small steps while some bond's opening lambda exceeds this (breaks at 1)
# the phases of ``solver.phase_steps``. The flight: no bond,
# the whole film this high above the plate even after FLIGHT_LOOKAHEAD long steps at its closing
# speed, from this long after the switch (the body jitter's window, switch + 50 ms, and 20 ms
# more) to the trajectory's end. The landing hold: from this long after the trajectory's end
FLIGHT_HEIGHT = 0.003  # m
FLIGHT_LOOKAHEAD = 10.0
FLIGHT_AFTER_SWITCH = 0.07  # s
LANDING_FINE = 0.05  # s
PHASE_EPS = 1e-9  # s: a step that ends this close after a phase's end ends in that phase


class PreStep:
    """Per-solve state shared by the pre-step function (kept small: it runs every step)."""

    def __init__(
        self, p: Platform, solver: exu.MainSolverImplicitSecondOrder, idle_bonds: bool = True
    ):
        s = p.spec
        self.p, self.solver = p, solver
        self.mbs = p.mbs
        self.data = p.mbs.systemData
        self.pad = PadTracker(
            p.mbs,
            p.pad_parts(),
            p.law,
            p.initial_pressure,
            s.mechanics.film.stop_radius,
            idle_bonds,
        )
        self.state = self.pad.state
        self.plate_index = self.pad.plate_index
        self.t0 = s.trajectory_start
        self.t_press_end = s.platform.protocol.settle + s.platform.protocol.press
        self.t_land = self.t0 + s.trajectory.duration
        self.press_integral = 0.0
        self.switched_at = math.nan
        self.bond_log: list[tuple[float, int]] = [(0.0, len(p.film_nodes))]
        self.bonded_log: list[np.ndarray] = [~self.state.broken]  # per bond_log entry
        self.mode = ""
        self.deadline = time.perf_counter() + s.solver.time_budget
        self.stop_reason: FailureReason | None = None
        self.stop_message = ""
        self.steps = 0
        self.t_settle = s.platform.protocol.settle
        self.step = s.solver.step
        self.phase_steps: dict[str, float] = dict(s.solver.phase_steps)
        self.h = self.h_next = self.step  # the step now taken; the next, set after the step
        self.long_steps = 0  # steps taken longer than ``step``

    def __call__(self, mbs, t: float) -> bool:
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        pad = self.pad.update(q, qd, self.solver.it.currentStepSize, t)
        n_bonded, lowest, lam_max = pad.bonded, pad.lowest, pad.load
        if pad.pushed:
            self.bond_log.append((t, n_bonded))
            self.bonded_log.append(~self.state.broken)
        if t <= self.t0:
            self._press(t, q, qd)
        if self.p.leg_update is not None:
            self.p.leg_update(t)
        if (
            math.isnan(self.switched_at)
            and n_bonded == 0
            and lowest > self.p.spec.platform.protocol.switch_height
        ):
            self.switched_at = t
            self.p.switch_time.SetValue(t)
        if not self.phase_steps:
            self._control_step(t, lam_max, lowest)
        else:
            self.long_steps += self.h > self.step
            self.h_next = self._next_step(t, qd, n_bonded, lowest)
        self.steps += 1
        if self.steps % 64 == 0:
            if not np.isfinite(q).all():
                return self._stop(
                    FailureReason.NON_FINITE_STATE, f"non-finite state at t = {t:.4f} s"
                )
            if time.perf_counter() > self.deadline:
                budget = self.p.spec.solver.time_budget
                return self._stop(
                    FailureReason.TIME_BUDGET,
                    f"time budget of {budget} s exceeded at t = {t:.4f} s",
                )
        return True

    def _phase(self, t: float) -> str | None:
        """The protocol's phase at time ``t`` where a long step may apply (config's
        ``LongPhase``); None from lift-off to the switch + FLIGHT_AFTER_SWITCH and in the
        landing's first LANDING_FINE, which always take ``step``."""
        if t < self.t_settle:
            return "settle"
        if t < self.t_press_end:
            return "press"
        if t < self.t0:
            return "press_hold"
        if t < self.t_land:
            return "flight" if t >= self.switched_at + FLIGHT_AFTER_SWITCH else None
        return "landing_hold" if t >= self.t_land + LANDING_FINE else None

    def _next_step(self, t: float, qd: Array, n_bonded: int, lowest: float) -> float:
        """The step from ``t``: its phase's step where it ends in a phase whose step is at least
        as long, and in the flight nothing sharp can happen within it (no bond, the film clear of
        the plate at its closing speed); ``step`` otherwise."""
        first = self._phase(t)
        h = self.phase_steps.get(first, self.step)  # type: ignore[arg-type]
        if h == self.step:
            return h
        last = self._phase(t + h - PHASE_EPS)
        if self.phase_steps.get(last, self.step) < h:  # type: ignore[arg-type]
            return self.step
        if "flight" in (first, last):
            z = self.pad.node_index + 1
            closing = max(float(qd[self.plate_index + 1] - qd[z].min()), 0.0)
            if n_bonded or lowest - FLIGHT_LOOKAHEAD * closing * h <= FLIGHT_HEIGHT:
                return self.step
        return h

    def after_step(self, mbs, t: float) -> bool:
        """Post-step (only with ``solver.phase_steps``): set the next step's size. Exudyn advances
        its clock by the step size before the pre-step runs, so a size set there would integrate
        one step over another length than the clock moved (the old mixed steps' kicks, "Time
        step"); set here, the next step's clock and integration both take it. ``maxStepSize``
        caps the adaptive step's regrowth after a Newton failure at the phase's step."""
        if self.h_next != self.h:
            self.h = self.h_next
            it = self.solver.it
            it.maxStepSize = self.h
            it.currentStepSize = self.h
        return True

    def _stop(self, reason: FailureReason, message: str) -> bool:
        """Record why the run stops; False tells Exudyn to stop."""
        self.stop_reason, self.stop_message = reason, message
        return False

    def _press(self, t: float, q: Array, qd: Array) -> None:
        """Integral control of the press depth so the sensor reads the pre-pressure a."""
        proto = self.p.spec.platform.protocol
        s = min(max((t - proto.settle) / proto.press, 0.0), 1.0)
        target = self.p.spec.pre_pressure * s * s * s * (10 - 15 * s + 6 * s * s)
        self.press_integral = press_control(
            self.p,
            self.plate_index,
            q,
            qd,
            self.solver.it.currentStepSize,
            target,
            self.press_integral,
        )

    def _control_step(self, t: float, lam_max: float, lowest: float) -> None:
        detaching = self.t0 <= t <= self.t_land and lam_max > NEAR_BREAK
        landing = (
            not math.isnan(self.switched_at) and lowest < LANDING_WINDOW and t < self.t_land + 0.05
        )
        small = detaching or landing or t < self.pad.last_break + PEEL_TAIL
        mode = "small" if small else "free"
        solver = self.p.spec.solver
        it = self.solver.it
        if mode != self.mode:
            self.mode = mode
            it.currentStepSize = solver.step if small else solver.free_step
        elif small and it.currentStepSize > solver.step:
            it.currentStepSize = solver.step


def press_control(
    p: Platform,
    plate_index: int,
    q: Array,
    qd: Array,
    h: float,
    target: float,
    integral: float,
    feedforward: bool = True,
) -> float:
    """Set the press depth so the sensor reads ``target`` (N, compression positive) by integral
    action on its error, with the depth that presses ``target`` through the foot as feedforward
    unless something else presses it (the slip test's sled); returns the updated integral (the
    caller keeps it between steps)."""
    k = p.series_stiffness
    integral = press_integral(p.spec.platform.sensor, plate_index, q, qd, h, target, integral, k)
    p.press_depth.SetValue((target / k if feedforward else 0.0) + integral)
    return integral


def press_integral(
    sensor: Sensor,
    plate_index: int,
    q: Array,
    qd: Array,
    h: float,
    target: float,
    integral: float,
    stiffness: float,
) -> float:
    """The press loop's integral after a step of ``h``: the depth (m) that brings the force
    ``sensor`` under the plate at ``plate_index`` reads to ``target`` (N, compression positive)
    through a press path of ``stiffness`` (N/m). The platform's press and the climbing robot's
    landing press share it."""
    compression = -(sensor.stiffness * q[plate_index + 1] + sensor.damping * qd[plate_index + 1])
    return integral + (target - compression) / stiffness * min(h / PRESS_TIME_CONSTANT, 1.0)
