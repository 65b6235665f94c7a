"""The climb's record: one row of every channel per record period, in a buffer sized for the run.

The channels (:data:`CHANNELS`) are what a climb returns (:func:`ftfof.climb.simulate.climb`
splits the rows with :func:`channel_slices`); the stance feet's force control reads its force
estimates back from the last rows (:meth:`Recorder.forces`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.feedforward import ESTIMATE_SAMPLES
from ftfof.climb.control.replan import BodyPlan
from ftfof.climb.gait import LEGS
from ftfof.climb.model import JOINTS, Climber
from ftfof.climb.sensing import Handles, SlipMeter
from ftfof.sim import film
from ftfof.sim.padstate import PadTracker

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


def channel_slices() -> dict[str, slice]:
    """Where each channel sits in a record row."""
    out, at = {}, 0
    for name, width in CHANNELS:
        out[name] = slice(at, at + width)
        at += width
    return out


class Recorder:
    """The rows recorded so far (``rows[:count]``), one each ``1 / rate`` seconds of the climb;
    rows past the buffer's end (a run longer than its gait) are dropped."""

    def __init__(
        self, robot: Climber, handles: Handles, pads: list[PadTracker], rate: float, slip: SlipMeter
    ):
        self.robot, self.handles, self.pads, self.slip = robot, handles, pads, slip
        self.sensor = robot.spec.platform.sensor
        self.every = 1.0 / rate
        self.next_record = 0.0
        n = math.ceil(robot.gait.end * rate) + 8
        self.width = sum(w for _, w in CHANNELS)
        self.rows = np.full((n, self.width), np.nan)
        self.count = 0
        self.force_columns = channel_slices()["force"]

    def due(self, t: float) -> bool:
        """Whether a record is due at ``t``."""
        return t >= self.next_record - 1e-9

    def record(
        self,
        t: float,
        state: tuple[Array, Array, Array],
        swing: int,
        stance: Array,
        plan: BodyPlan,
        torque: Array,
    ) -> None:
        """Record the solved ``state`` (coordinates, rates, accelerations) at ``t``: ``swing``
        the leg whose step it is, ``stance`` the feet holding, ``plan`` the body's, ``torque``
        the servos' now; the next record falls one period later."""
        if self.count < len(self.rows):
            self.rows[self.count] = self._row(t, state, swing, stance, plan, torque)
            self.count += 1
        self.next_record += self.every

    def _row(
        self,
        t: float,
        state: tuple[Array, Array, Array],
        swing: int,
        stance: Array,
        plan: BodyPlan,
        torque: Array,
    ) -> Array:
        q, qd, qdd = state
        h, sensor, mass = self.handles, self.sensor, self.sensor.plate_mass
        px, pz = h.patches, h.patches + 1
        fx = sensor.stiffness * q[px] + sensor.damping * qd[px] + mass * qdd[px]
        fz = sensor.stiffness * q[pz] + sensor.damping * qd[pz] + mass * qdd[pz]
        foot = h.foot_ref + np.stack([q[h.feet], q[h.feet + 1]], axis=1)
        bonds = np.array([np.count_nonzero(~p.state.broken) for p in self.pads], float)
        lowest = np.array(
            [float(np.min(q[idx + 1] - q[pz[i]])) for i, idx in enumerate(h.node_index)]
        )
        curvature = np.zeros(LEGS)
        if swing >= 0:
            curvature[swing] = self._curvature(q, swing)
        body_plan, _ = plan(np.array([t]))
        slip = self.slip.velocity(q, t, stance, "record")
        forces = np.stack([fx, fz], axis=1).ravel()
        state = [h.body(q), h.body(qd), h.body(qdd), body_plan, foot.ravel(), forces]
        pads = [bonds, lowest, curvature, q[h.joints], torque]
        return np.concatenate([[t], *state, *pads, [swing], slip])

    def _curvature(self, q: Array, leg: int) -> float:
        """The free-span curvature of ``leg``'s film now (:mod:`ftfof.sim.film`)."""
        idx = self.handles.node_index[leg]
        coords = q[idx[:, None] + np.arange(4)][None]
        coords = coords - np.array([0.0, q[self.handles.patches[leg] + 1], 0.0, 0.0])
        bonded = ~self.pads[leg].state.broken[None]
        parts = self.robot.pads[leg]
        return float(
            film.free_span_curvature(coords, parts.x_ref, self.robot.clamp_edge, bonded)[0]
        )

    def forces(self, leg: int) -> tuple[Array, Array] | None:
        """The wall's force on ``leg``'s foot over the last ESTIMATE_SAMPLES records: (f_n, f_t),
        f_n > 0 pressing (the force channel is the pad's on the wall: negated); None before
        there are that many."""
        if self.count < ESTIMATE_SAMPLES:
            return None
        f = self.rows[self.count - ESTIMATE_SAMPLES : self.count, self.force_columns]
        return -f[:, 2 * leg + 1], -f[:, 2 * leg]
