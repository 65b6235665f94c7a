"""One pad's per-step bookkeeping in a solver loop: its bonds, idle connectors and curvature stops.

The platform has one pad and the climbing robot four; each pre-step function keeps one
:class:`PadTracker` per pad. Before each step it updates the bond states and pushes the changed
ones to their connectors (:mod:`ftfof.sim.bonds`), switches the connectors of broken bonds clear
of the wall off and on again near it, and arms the film's curvature stops where the film bends
near them (:mod:`ftfof.sim.film`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ftfof.sim import bonds, film

Array = NDArray[np.float64]


@dataclass(frozen=True)
class PadParts:
    """The Exudyn items of one pad and the geometry its bond law needs."""

    film_nodes: list[Any]
    film_elements: list[Any]
    bend_stop: Any  # the curvature-stop moment law, set on an element while it is armed
    bonds: list[Any]  # one connector per film node
    plate_node: Any  # the plate (or wall patch) the bonds hold to
    x_ref: Array  # film node reference x, relative to the plate's reference
    area: Array  # pad area per bond


@dataclass(frozen=True)
class PadStep:
    """What one update saw: pushes made, bonds holding, the film's lowest height above the plate
    and the largest bond load (opening lambda / r, 1 once a bond softens)."""

    pushed: int
    bonded: int
    lowest: float
    load: float


class PadTracker:
    """The bond state machine of one pad, pushed into its connectors between solver steps."""

    def __init__(
        self,
        mbs: Any,
        parts: PadParts,
        law: bonds.BondLaw,
        initial_pressure: float,
        stop_radius: float,
        idle_bonds: bool = True,
    ):
        self.mbs, self.parts = mbs, parts
        n = len(parts.film_nodes)
        self.node_index = np.array([mbs.GetNodeODE2Index(k) for k in parts.film_nodes], np.int64)
        self.plate_index = int(mbs.GetNodeODE2Index(parts.plate_node))
        self.state = bonds.BondState.bonded(parts.x_ref, initial_pressure, law)
        # the state's arrays in :func:`bonds.step`'s order, gathered once: the kernel updates
        # them in place, and gathering them anew every step cost 4 % of a sample's wall time
        self.state_arrays = self.state.arrays()
        self.kernel_law = bonds.kernel_law(law)
        self.push = np.zeros(n, dtype=np.int64)
        self.kind = np.zeros_like(self.push)
        self.idle_bonds = idle_bonds
        self.idle = np.zeros(n, dtype=bool)
        self.idle_changed = np.zeros(n, dtype=np.int64)
        self.armed = np.zeros(len(parts.film_elements), dtype=bool)
        self.changed = np.zeros(len(parts.film_elements), dtype=np.int64)
        self.arm_at, self.disarm_at = film.ARM / stop_radius, film.DISARM / stop_radius
        self.last_break = -np.inf

    @property
    def bonded_share(self) -> float:
        """The bonded share of the pad's area (a graded film's bonds hold unequal areas)."""
        area = self.parts.area
        return float(area[~self.state.broken].sum() / area.sum())

    def update(self, q: Array, qd: Array, h: float, t: float) -> PadStep:
        """Advance the bond states to the solver's state (q, qd) before a step of ``h``."""
        parts = self.parts
        n_push, n_bonded, lowest, load = bonds.step(
            q,
            qd,
            self.node_index,
            self.plate_index,
            parts.x_ref,
            parts.area,
            *self.state_arrays,
            h,
            self.kernel_law,
            self.push,
            self.kind,
        )
        if n_push:
            self._apply(n_push, t)
        if self.idle_bonds:
            self._idle(q, qd, h)
        n_armed = film.arm_stops(
            q, self.node_index, parts.x_ref, self.armed, self.arm_at, self.disarm_at, self.changed
        )
        if n_armed:
            self._arm(n_armed)
        return PadStep(n_push, n_bonded, lowest, load)

    def _apply(self, n_push: int, t: float) -> None:
        """Push the changed bonds' state to their connectors (each bond's values gathered as
        Python floats in one go: the loop runs on most steps of a pull)."""
        st, setp, objects = self.state, self.mbs.SetObjectParameter, self.parts.bonds
        push = self.push[:n_push]
        kinds = self.kind[:n_push].tolist()
        anchor, slider = st.anchor[push].tolist(), st.slider_pushed[push].tolist()
        broken, scale = st.broken[push].astype(float).tolist(), st.scale[push].tolist()
        for j, i in enumerate(push.tolist()):
            kind = kinds[j]
            if kind & (bonds.REBOND | bonds.SLIDE):
                setp(objects[i], "offset", [anchor[j], 0.0, slider[j]])
            if kind & (bonds.BREAK | bonds.SCALE | bonds.REBOND):
                setp(objects[i], "damping", [broken[j], scale[j], 0.0])
            if kind & bonds.BREAK:
                self.last_break = t

    def _idle(self, q: Array, qd: Array, h: float) -> None:
        """Switch off the connectors of broken bonds clear of the plate, on again near it."""
        n = bonds.idle_changes(
            q,
            qd,
            self.node_index,
            self.plate_index,
            self.state.broken,
            self.idle,
            h,
            self.idle_changed,
        )
        for i in self.idle_changed[:n]:
            self.mbs.SetObjectParameter(self.parts.bonds[i], "activeConnector", not self.idle[i])

    def _arm(self, n: int) -> None:
        """Put the curvature stop on the elements just armed, take it off those disarmed."""
        for e in self.changed[:n]:
            law = self.parts.bend_stop if self.armed[e] else 0
            self.mbs.SetObjectParameter(
                self.parts.film_elements[e], "bendingMomentUserFunction", law
            )
