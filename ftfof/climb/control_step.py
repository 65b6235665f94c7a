"""The solver loop's control step: the stance feet's force control at its own rate.

At each control period it hands the controller (``climb.controller``,
:mod:`ftfof.climb.control.feedforward`) the trunk's state, the body's plan, the legs' joints,
the feet on the wall, the stance, each stance pad's slide (:class:`ftfof.climb.sensing.SlipMeter`)
and the recorded wall forces; it answers with the servos' feed-forward torques and, where a slip
made it re-plan, a new body plan.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.feedforward import CONTROL_RATE_HZ
from ftfof.climb.control.replan import BodyPlan
from ftfof.climb.gait import LEGS
from ftfof.climb.model import JOINTS
from ftfof.climb.sensing import Handles, SlipMeter

Array = NDArray[np.float64]
ForceWindow = Callable[[int], tuple[Array, Array] | None]  # a leg's recent (f_n, f_t), or None


class Controller(Protocol):
    """What the loop needs of a stance controller (:class:`FeedForward` is one)."""

    anchored: Array  # (4,) bool: the feet it holds where they are on the wall

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
    ) -> tuple[Array, BodyPlan | None]: ...


class ControlStep:
    """Runs ``control`` once per control period, from t = 0."""

    def __init__(self, control: Controller, handles: Handles, slip: SlipMeter, forces: ForceWindow):
        self.control, self.handles, self.slip, self.forces = control, handles, slip, forces
        self.next_control = 0.0

    @property
    def anchored(self) -> Array:
        return self.control.anchored

    def due(self, t: float) -> bool:
        """Whether a control step is due at ``t``."""
        return t >= self.next_control - 1e-12

    def step(
        self, t: float, q: Array, qd: Array, plan: BodyPlan, stance: Array
    ) -> tuple[Array, BodyPlan | None]:
        """One control step on the state ``q``, ``qd`` tracking ``plan`` with the feet
        ``stance`` holding: (4, 3) feed-forward torques and the new plan (None: keep it)."""
        h = self.handles
        out = self.control.step(
            t,
            h.body(q).copy(),
            h.body(qd).copy(),
            plan,
            q[h.joints].reshape(LEGS, JOINTS),
            h.foot_ref[:, 0] + q[h.feet],
            stance,
            self.slip.velocity(q, t, stance, "control"),
            self.forces,
        )
        self.next_control += 1.0 / CONTROL_RATE_HZ
        return out
