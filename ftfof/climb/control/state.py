"""What a climb's controller believes, senses and did, shared by its parts
(:mod:`ftfof.climb.control.feedforward` and the re-planning it composes)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.replan import BodyPlan
from ftfof.identify.estimate import Estimate

Array = NDArray[np.float64]

# a foot's last ESTIMATE_SAMPLES forces on it (f_n, f_t), or None while there are fewer
ForceWindow = Callable[[int], tuple[Array, Array] | None]


@dataclass(frozen=True)
class Pads:
    """Each foot's pad as the controller believes it."""

    friction: Array  # (4,) mu
    adhesion: Array  # (4,) F_adh, N: the shear capacity seen as normal load
    pull_off: Array  # (4,) the most each pad holds pulled normal to the wall, N


@dataclass
class Counts:
    """What the controller did over a climb (the climb's JSON reports it)."""

    solves: int = 0
    failed: int = 0  # steps whose QP found no answer: no feed-forward for them
    slips: int = 0  # slips declared (a foot's rising edge)
    estimates: int = 0  # pads re-estimated
    replans: int = 0  # new plans the re-planner gave


@dataclass(frozen=True)
class SlipEstimate:
    """What the estimator made of one slip: a foot's pad fitted from its force window at the
    slip's declaration, in the slip law's tangential form (``identify``'s: F_adh in N of
    shear), whether or not the controller believes it."""

    time: float  # s: the control step that declared the slip
    foot: int
    fit: Estimate


@dataclass(frozen=True)
class Sensed:
    """The robot at one control step, as the loop hands it to the controller (wall frame)."""

    time: float  # s
    body: Array  # (3,) x, z, pitch of the trunk
    body_rate: Array  # (3,)
    plan: BodyPlan  # the body plan the loop tracks
    stance: Array  # (4,) bool: the stance feet
    feet: Array  # (4,) each foot's x on the wall, m
    forces: ForceWindow
