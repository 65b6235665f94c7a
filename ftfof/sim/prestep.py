"""The solver loop's pre-step function: everything the protocol changes between two steps.

Before each step it updates the bond states and pushes the changed ones to their connectors
(:mod:`ftfof.sim.bonds`), switches idle bonds and the film's curvature stops on or off, holds
the press depth on the pre-pressure until the trajectory starts, throws the photoelectric switch
once the pad is off and clear, and picks the step: ``solver.step`` while bonds break or the pad
lands and ``solver.free_step`` elsewhere (the defaults are one step throughout, since a change of
step shakes the simulated body: docs/simulator.md, "Time step"). A non-finite state or the time
budget stops the run, with the reason kept for the sample's record.
"""

from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.sim import bonds, film
from ftfof.sim.model import Platform
from ftfof.sim.records import FailureReason

Array = NDArray[np.float64]
PRESS_TIME_CONSTANT = 0.01  # s, integral action of the pre-pressure loop
LANDING_WINDOW = 0.003  # m: below this lowest-film height after detachment, take small steps
PEEL_TAIL = 0.03  # s of small steps after the last bond breaks (release ringing, IMU peak)
NEAR_BREAK = 0.3  # small steps while some bond's opening lambda exceeds this (breaks at 1)


class PreStep:
    """Per-solve state shared by the pre-step function (kept small: it runs every step)."""

    def __init__(
        self, p: Platform, solver: exu.MainSolverImplicitSecondOrder, idle_bonds: bool = True
    ):
        s = p.spec
        self.p, self.solver = p, solver
        self.mbs = p.mbs
        self.data = p.mbs.systemData
        self.node_index = np.array(
            [p.mbs.GetNodeODE2Index(n) for n in p.film_nodes], dtype=np.int64
        )
        self.plate_index = int(p.mbs.GetNodeODE2Index(p.plate_node))
        self.state = bonds.BondState.bonded(p.x_ref, p.initial_pressure, p.law)
        self.kernel_law = bonds.kernel_law(p.law)
        self.push = np.zeros(len(p.film_nodes) * 2, dtype=np.int64)
        self.kind = np.zeros_like(self.push)
        self.t0 = s.trajectory_start
        self.t_press_end = s.platform.protocol.settle + s.platform.protocol.press
        self.t_land = self.t0 + s.trajectory.duration
        self.press_integral = 0.0
        self.switched_at = math.nan
        self.last_break = -math.inf
        self.bond_log: list[tuple[float, int]] = [(0.0, len(p.film_nodes))]
        self.bonded_log: list[np.ndarray] = [~self.state.broken]  # per bond_log entry
        self.idle_bonds = idle_bonds
        self.idle = np.zeros(len(p.film_nodes), dtype=bool)
        self.idle_changed = np.zeros(len(p.film_nodes), dtype=np.int64)
        self.armed = np.zeros(len(p.film_elements), dtype=bool)
        self.changed = np.zeros(len(p.film_elements), dtype=np.int64)
        stop_radius = s.mechanics.film.stop_radius
        self.arm_at, self.disarm_at = film.ARM / stop_radius, film.DISARM / stop_radius
        self.mode = ""
        self.deadline = time.perf_counter() + s.solver.time_budget
        self.stop_reason: FailureReason | None = None
        self.stop_message = ""
        self.steps = 0

    def __call__(self, mbs, t: float) -> bool:
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        st = self.state
        h = self.solver.it.currentStepSize
        n_push, n_bonded, lowest, lam_max = bonds.step(
            q,
            qd,
            self.node_index,
            self.plate_index,
            self.p.x_ref,
            self.p.area,
            st.anchor,
            st.broken,
            st.p_max,
            st.rate,
            st.scale,
            st.opening_rate,
            st.opening_max,
            h,
            self.kernel_law,
            self.push,
            self.kind,
        )
        if n_push:
            self._apply(n_push, t)
            self.bond_log.append((t, n_bonded))
            self.bonded_log.append(~st.broken)
        if self.idle_bonds:
            self._idle(q, qd, st.broken, h)
        n_armed = film.arm_stops(
            q, self.node_index, self.p.x_ref, self.armed, self.arm_at, self.disarm_at, self.changed
        )
        if n_armed:
            self._arm(n_armed)
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
        self._control_step(t, lam_max, lowest)
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

    def _stop(self, reason: FailureReason, message: str) -> bool:
        """Record why the run stops; False tells Exudyn to stop."""
        self.stop_reason, self.stop_message = reason, message
        return False

    def _apply(self, n_push: int, t: float) -> None:
        st, setp = self.state, self.mbs.SetObjectParameter
        for j in range(n_push):
            i, kind = int(self.push[j]), int(self.kind[j])
            obj = self.p.bonds[i]
            if kind == bonds.BREAK:
                setp(obj, "damping", [1.0, float(st.scale[i]), 0.0])
                self.last_break = t
            else:
                if kind == bonds.REBOND:
                    setp(obj, "offset", [float(st.anchor[i]), 0.0, 0.0])
                setp(obj, "damping", [0.0, float(st.scale[i]), 0.0])

    def _idle(self, q: Array, qd: Array, broken: NDArray[np.bool_], h: float) -> None:
        """Switch off the connectors of broken bonds clear of the plate, on again near it."""
        n = bonds.idle_changes(
            q,
            qd,
            self.node_index,
            self.plate_index,
            broken,
            self.idle,
            h,
            self.idle_changed,
        )
        for i in self.idle_changed[:n]:
            self.mbs.SetObjectParameter(self.p.bonds[i], "activeConnector", not self.idle[i])

    def _arm(self, n: int) -> None:
        """Put the curvature stop on the elements just armed, take it off those disarmed."""
        for e in self.changed[:n]:
            law = self.p.bend_stop if self.armed[e] else 0
            self.mbs.SetObjectParameter(self.p.film_elements[e], "bendingMomentUserFunction", law)

    def _press(self, t: float, q: Array, qd: Array) -> None:
        """Integral control of the press depth so the sensor reads the pre-pressure a."""
        spec = self.p.spec
        proto = spec.platform.protocol
        s = min(max((t - proto.settle) / proto.press, 0.0), 1.0)
        target = spec.pre_pressure * s * s * s * (10 - 15 * s + 6 * s * s)
        sensor = spec.platform.sensor
        compression = -(
            sensor.stiffness * q[self.plate_index + 1] + sensor.damping * qd[self.plate_index + 1]
        )
        k = self.p.series_stiffness
        h = self.solver.it.currentStepSize
        self.press_integral += (target - compression) / k * min(h / PRESS_TIME_CONSTANT, 1.0)
        self.p.press_depth.SetValue(target / k + self.press_integral)

    def _control_step(self, t: float, lam_max: float, lowest: float) -> None:
        detaching = self.t0 <= t <= self.t_land and lam_max > NEAR_BREAK
        landing = (
            not math.isnan(self.switched_at) and lowest < LANDING_WINDOW and t < self.t_land + 0.05
        )
        small = detaching or landing or t < self.last_break + PEEL_TAIL
        mode = "small" if small else "free"
        solver = self.p.spec.solver
        it = self.solver.it
        if mode != self.mode:
            self.mode = mode
            it.currentStepSize = solver.step if small else solver.free_step
        elif small and it.currentStepSize > solver.step:
            it.currentStepSize = solver.step
