"""One step of the crawl as the CoM planner (:mod:`ftfof.climb.control.planner`) takes it: the
feet on the wall, what holds each there, and the CoM's start and goal.

Frame and signs: x up the wall, z out of it, gravity along -x (the climbing model's frame). A
foot's force f = (f_t, f_n) is the wall's force on the foot: f_t along +x, f_n along +z, so
f_n > 0 presses the pad into the wall and f_n < 0 pulls on it. A pad of friction ``mu`` and
adhesion ``F_adh`` holds while

    f_n >= -F_pull                 it does not pull off the wall (F_pull: F_adh unless the
                                   pad's pull-off is given, Foothold.pull_off),
    |f_t| <= mu (f_n + F_adh)      it does not slide (the pyramid is two lines in 2-D),

that is while its adhesion-shifted force c = (f_t, f_n + F_adh) lies in the plain cone: the
paper's contact force beside a constant magnetic one. Moments are a x b = a_x b_z - a_z b_x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.config import GRAVITY, LEG_NAMES

Array = NDArray[np.float64]
G = np.array([-GRAVITY, 0.0])


@dataclass(frozen=True)
class Foothold:
    """One foot on the wall and what holds it there."""

    position: Array  # (2,) the pad's contact point (x, z), m
    mu: float  # friction coefficient
    adhesion: float  # F_adh, N: the cone's shift (the shear capacity seen as normal load)
    weight: float = 1.0  # scales the foot's W_f: a heavier weight gives it less of the load
    pull_off: float | None = None  # N: the most the pad holds pulled off (None: F_adh)

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", np.asarray(self.position, float))
        if self.mu <= 0 or self.adhesion < 0 or self.weight <= 0:
            raise ValueError(f"a foothold needs mu > 0, F_adh >= 0, weight > 0: {self}")
        if self.pull_off is not None and self.pull_off < 0:
            raise ValueError(f"a foothold needs pull-off >= 0: {self}")

    @property
    def pull(self) -> float:
        """The most the pad holds pulled off the wall, N: its pull-off, or F_adh without one."""
        return self.adhesion if self.pull_off is None else float(self.pull_off)


@dataclass(frozen=True)
class Step:
    """One step: the CoM from ``start`` to ``goal`` (at rest at both) while ``feet[swing]``
    moves to ``landing``; pre-swing, swing and post-swing last ``durations``."""

    mass: float  # kg, the whole robot
    start: Array  # (2,) CoM, m
    goal: Array  # (2,) CoM, m
    feet: tuple[Foothold, ...]  # every foot before the step, in ``names`` order
    swing: int  # the stepping foot
    landing: Foothold  # the stepping foot after the step
    durations: tuple[float, float, float]  # s
    momentum_rate: float = 0.0  # L', N m, the centroidal angular momentum's rate
    names: tuple[str, ...] = LEG_NAMES

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", np.asarray(self.start, float))
        object.__setattr__(self, "goal", np.asarray(self.goal, float))
        if len(self.feet) != len(self.names) or not 0 <= self.swing < len(self.feet):
            raise ValueError(f"{len(self.feet)} feet for {self.names}, stepping foot {self.swing}")
        if self.mass <= 0 or min(self.durations) <= 0:
            raise ValueError(
                f"a step needs a mass and durations > 0: {self.mass}, {self.durations}"
            )

    @property
    def direction(self) -> Array:
        """The CoM's line, start to goal; up the wall when the goal is the start."""
        delta = self.goal - self.start
        norm = math.hypot(*delta)
        return delta / norm if norm > 0 else np.array([1.0, 0.0])

    def stance(self, phase: int) -> tuple[tuple[Foothold, ...], NDArray[np.bool_]]:
        """Phase ``phase``'s footholds (0 pre-swing, 1 swing, 2 post-swing), the stepping foot
        at its landing after the swing, and which of them hold."""
        feet = list(self.feet)
        if phase == 2:
            feet[self.swing] = self.landing
        holds = np.ones(len(feet), bool)
        holds[self.swing] = phase != 1
        return tuple(feet), holds
