"""The solver loop's pre-step function: everything the protocol changes between two steps.

Before each step it updates the pad (:class:`ftfof.sim.padstate.PadTracker`: bond states,
idle connectors, the film's curvature stops), holds
the press depth on the pre-pressure until the trajectory starts, throws the photoelectric switch
once the pad is off and clear, and picks the step (:class:`ftfof.sim.stepsize.StepSize`: ``step``
while bonds break or the pad lands, longer steps in the phases ``solver.phase_steps`` names). A
non-finite state or the time budget stops the run, with the reason kept for the sample's record.
"""

from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.sim.model import Platform
from ftfof.sim.padstate import PadTracker
from ftfof.sim.press import press_control
from ftfof.sim.proof import ProofPull
from ftfof.sim.records import FailureReason
from ftfof.sim.stepsize import StepSize

Array = NDArray[np.float64]


class PreStep(StepSize):
    """Per-solve state shared by the pre-step function (kept small: it runs every step)."""

    def __init__(
        self, p: Platform, solver: exu.MainSolverImplicitSecondOrder, idle_bonds: bool = True
    ):
        s = p.spec
        self.p = p
        self.mbs = p.mbs
        self.data = p.mbs.systemData
        pad = PadTracker(
            p.mbs,
            p.pad_parts(),
            p.law,
            p.initial_pressure,
            s.mechanics.film.stop_radius,
            idle_bonds,
        )
        super().__init__(s, solver, pad)
        self.state = self.pad.state
        self.press_integral = 0.0
        self.bond_log: list[tuple[float, int]] = [(0.0, len(p.film_nodes))]
        self.bonded_log: list[np.ndarray] = [~self.state.broken]  # per bond_log entry
        self.deadline = time.perf_counter() + s.solver.time_budget
        self.stop_reason: FailureReason | None = None
        self.stop_message = ""
        self.steps = 0
        self.proof = None if s.proof_pull is None else ProofPull(p, self.plate_index)

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
        elif self.proof is not None and t > self.t_proof:
            h = self.solver.it.currentStepSize
            if not self.proof(t, q, qd, h, self.pad.bonded_share):
                return False  # a further tenth of the pad let go: the test ends, no failure
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

    @property
    def proof_let_go(self) -> bool:
        """The proof pull ended the run: a further tenth of the pad let go (no failure)."""
        return self.proof is not None and self.proof.let_go

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
