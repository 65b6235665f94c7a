"""When a climb stops early: the robot fell (a stance pad let go, the body left its plan), or the
run went wrong (a non-finite state, the wall-time budget spent). A fall ends the run cleanly with
what was recorded; a stop makes the climb fail with its reason (:mod:`ftfof.climb.simulate`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.replan import BodyPlan
from ftfof.climb.gait import LEGS
from ftfof.config import LEG_NAMES, Climb

Array = NDArray[np.float64]
CHECK_EVERY = 64  # solver steps between two checks of the state and the clock (they cost)


@dataclass
class Fall:
    time: float
    why: str


class Watchdog:
    """The run's checks; ``stopped`` says why a check stopped it, ``fall`` why the robot fell."""

    def __init__(self, climb: Climb, start: float, tree: int):
        self.fall_distance, self.budget = climb.fall_distance, climb.time_budget
        self.start, self.tree = start, tree  # the first lift-off; the trunk's coordinates
        self.deadline = time.perf_counter() + climb.time_budget
        self.steps = 0
        self.stopped = ""
        self.fall: Fall | None = None

    def step(self, t: float, q: Array) -> bool:
        """Count a solver step; every CHECK_EVERY steps, False (stop) on a non-finite state or
        past the time budget."""
        self.steps += 1
        if self.steps % CHECK_EVERY == 0:
            if not np.isfinite(q).all():
                self.stopped = f"non-finite state at t = {t:.4f} s"
                return False
            if time.perf_counter() > self.deadline:
                self.stopped = f"time budget of {self.budget} s exceeded at t = {t:.4f} s"
                return False
        return True

    def fell(self, t: float, q: Array, held: Array, swing: int, plan: BodyPlan) -> bool:
        """A stance pad let go (``held``: each pad bonded), or the body left ``plan`` by more
        than ``climb.fall_distance``: the robot has fallen. ``swing`` is the leg in the air or
        in its landing hold (-1 after: its pad then holds the robot too)."""
        stance = np.ones(LEGS, dtype=bool)
        if swing >= 0:
            stance[swing] = False
        if t > self.start and not held[stance].all():
            leg = int(np.flatnonzero(stance & ~held)[0])
            self.fall = Fall(t, f"the {LEG_NAMES[leg]} stance pad let go at t = {t:.3f} s")
        body, _ = plan(np.array([t]))
        b = self.tree
        off = math.hypot(q[b] - body[0], q[b + 1])
        if self.fall is None and off > self.fall_distance:
            self.fall = Fall(t, f"the body left its plan by {1e3 * off:.1f} mm at t = {t:.3f} s")
        return self.fall is not None
