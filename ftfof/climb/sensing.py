"""Where the climbing robot's parts sit in the solver's coordinates, and each stance pad's slide.

The solver loop's parts (:mod:`ftfof.climb.loop`) read the same coordinates: the trunk's floating
base and joints in the kinematic tree, each foot's node, each wall patch's sensor plate, each
pad's film nodes. :class:`Handles` holds those indices once; :class:`SlipMeter` reads each stance
pad's velocity along its patch from them.
"""

from __future__ import annotations

from dataclasses import dataclass

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.climb.gait import LEGS
from ftfof.climb.model import BASE, JOINTS, Climber
from ftfof.sim.padstate import PadTracker

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Handles:
    """Indices into the solver's coordinates (ODE2) of one built climber."""

    tree: int  # the trunk's floating base: x, z, pitch, then each leg's joints
    feet: NDArray[np.int64]  # (4,) each foot node's x (z follows)
    patches: NDArray[np.int64]  # (4,) each wall patch's sensor plate x (z follows)
    foot_ref: Array  # (4, 2) each foot's reference x, z: its coordinates are displacements
    node_index: list[NDArray[np.int64]]  # each pad's film nodes' x (4 coordinates per node)

    @classmethod
    def of(cls, robot: Climber, pads: list[PadTracker]) -> Handles:
        mbs = robot.mbs
        ref = np.array([mbs.GetNodeOutput(f, exu.OutputVariableType.Position,
                                          exu.ConfigurationType.Reference)[:2]
                        for f in robot.feet])  # fmt: skip
        return cls(
            tree=int(mbs.GetNodeODE2Index(robot.tree_node)),
            feet=np.array([mbs.GetNodeODE2Index(f) for f in robot.feet], np.int64),
            patches=np.array([p.plate_index for p in pads], np.int64),
            foot_ref=ref,
            node_index=[p.node_index for p in pads],
        )

    @property
    def joints(self) -> slice:
        """The legs' joint angles, leg after leg."""
        return slice(self.tree + BASE, self.tree + BASE + JOINTS * LEGS)

    def body(self, q: Array) -> Array:
        """(3,) the trunk's x, z, pitch (or their rates, from the rates)."""
        return q[self.tree : self.tree + BASE]


class SlipMeter:
    """Each stance pad's velocity along its wall patch, 0 off the stance: its film nodes' mean
    position (the foot above it rocks on its ankle; the pad's nodes are what slide) since a
    clock's last reading. Not the nodes' velocities: on the plate's stiff backing they chatter
    +-5 mm/s from one solver step to the next while the pad stays within 10 um, and the records,
    a step apart, read that as a steady slide. Each reader keeps its own clock."""

    def __init__(self, handles: Handles):
        self.handles = handles
        self.clocks: dict[str, tuple[float, Array]] = {}  # (t, film positions) per reader

    def velocity(self, q: Array, t: float, stance: Array, clock: str) -> Array:
        """(4,) m/s since ``clock``'s last reading (0 at its first)."""
        h = self.handles
        position = np.array([q[idx].mean() for idx in h.node_index]) - q[h.patches]
        last_t, last = self.clocks.get(clock, (t, position))
        self.clocks[clock] = (t, position)
        rate = (position - last) / (t - last_t) if t > last_t else np.zeros(LEGS)
        return np.where(stance, rate, 0.0)
