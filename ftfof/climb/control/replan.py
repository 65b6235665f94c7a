"""The seam between the slip controller and a body re-planner (climbing_slip's one-step CoM plan).

When a stance foot slips, the ``replan`` and ``both`` controllers estimate that foot's pad
(mu, F_adh) from its last forces and hand a :class:`ReplanRequest` to a :data:`Replanner`. It
answers with a new :data:`BodyPlan`, which the solver loop then tracks (its feet's joint targets
and the trunk wrench's PD), or None to keep the plan it has. The loop starts on the gait's own
plan, :meth:`ftfof.climb.gait.Gait.body`, which is a BodyPlan.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

# The body's planned x along the wall (m) and its rate (m/s) at each of the times t (s).
BodyPlan = Callable[[Array], tuple[Array, Array]]


@dataclass(frozen=True)
class ReplanRequest:
    """What the robot knows when a foot slips (wall frame: x up, z out; legs FL FR HL HR)."""

    time: float  # s
    foot: int  # the foot that slips
    friction: Array  # (4,) each pad's mu as the controller now believes it (estimated or nominal)
    adhesion: Array  # (4,) each pad's F_adh, N, likewise
    stance: Array  # (4,) bool: the feet on the wall
    feet: Array  # (4,) each foot's x on the wall, m
    body: Array  # (3,) x, z, pitch of the trunk
    body_rate: Array  # (3,)
    plan: BodyPlan  # the plan the loop tracks now
    pull_off: Array | None = None  # (4,) the most each pad holds pulled off, N (None: F_adh)


Replanner = Callable[[ReplanRequest], BodyPlan | None]


def keep_plan(request: ReplanRequest) -> BodyPlan | None:
    """The re-planner until the CoM planner lands: it keeps the plan the loop has."""
    return None
