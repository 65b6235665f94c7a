"""The solver loop's step size: what the pre-step (:class:`ftfof.sim.prestep.PreStep`) takes next.

``solver.step`` while bonds break or the pad lands and ``solver.free_step`` elsewhere (the
defaults are one step throughout, since a change of step shakes the simulated body:
docs/simulator.md, "Time step"). With ``solver.phase_steps`` a longer step in the protocol's
phases named there (:meth:`StepSize._phase` names the phase of a time), set after a step so that
Exudyn's clock and its integration agree (:meth:`StepSize.after_step`).
"""

from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.sim.padstate import PadTracker
from ftfof.sim.spec import SampleSpec

Array = NDArray[np.float64]
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


class StepSize:
    """The step-size state of one solve: the protocol's times, the switch time (the pre-step
    throws the switch) and the step now taken; the pre-step picks each step with it."""

    def __init__(
        self, spec: SampleSpec, solver: exu.MainSolverImplicitSecondOrder, pad: PadTracker
    ):
        self.solver, self.pad = solver, pad
        self.plate_index = pad.plate_index
        self.settings = spec.solver
        protocol = spec.platform.protocol
        self.t_settle = protocol.settle
        self.t_press_end = protocol.settle + protocol.press
        self.t0 = spec.trajectory_start
        self.t_land = self.t0 + spec.trajectory.duration
        # the proof pull's start; none: the landing hold runs to the end
        self.t_proof = spec.landing_end if spec.proof_pull is not None else math.inf
        self.switched_at = math.nan
        self.mode = ""
        self.step = spec.solver.step
        self.phase_steps: dict[str, float] = dict(spec.solver.phase_steps)
        self.h = self.h_next = self.step  # the step now taken; the next, set after the step
        self.long_steps = 0  # steps taken longer than ``step``

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
        if t < self.t_proof:
            return "landing_hold" if t >= self.t_land + LANDING_FINE else None
        return None  # the proof pull: its pad is loaded toward its break all along

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

    def _control_step(self, t: float, lam_max: float, lowest: float) -> None:
        """Without phase steps: ``step`` near a break, in the landing and the peel's tail,
        ``free_step`` elsewhere, set before the step."""
        detaching = self.t0 <= t <= self.t_land and lam_max > NEAR_BREAK
        landing = (
            not math.isnan(self.switched_at) and lowest < LANDING_WINDOW and t < self.t_land + 0.05
        )
        pulled = t > self.t_proof  # the proof pull loads the pad toward its break all along
        small = detaching or landing or pulled or t < self.pad.last_break + PEEL_TAIL
        mode = "small" if small else "free"
        solver = self.settings
        it = self.solver.it
        if mode != self.mode:
            self.mode = mode
            it.currentStepSize = solver.step if small else solver.free_step
        elif small and it.currentStepSize > solver.step:
            it.currentStepSize = solver.step
