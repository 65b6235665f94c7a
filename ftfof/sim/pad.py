"""The adhesive pad in the Exudyn system: the film and its bond connectors (docs/simulator.md).

- film: ANCF cable elements (exact EI, EA) lying on the plate, x in [0, lf], each with a
  curvature stop (:func:`_bending_moment`) that the solver loop arms only while the element is
  bent near it (the symbolic moment law costs +70 % run time when always on), held by the foot
  (:mod:`ftfof.sim.foot`: the grip's clamp or the plate's backing);
- one cohesive bond connector per film node (law in :mod:`ftfof.sim.bonds`), all sharing one
  symbolic user function; their state lives in the connector parameters (stiffness =
  [K_t A, K A, Kc A], damping = [broken, phi * R * (1 - D), 0], offset = [bond anchor, 0,
  friction slider's anchor]; a 2D connector has no use for the third slots).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import exudyn as exu
import numpy as np
from exudyn.advancedUtilities import CreateSymbolicUserFunction
from exudyn.itemInterface import (
    CartesianSpringDamper,
    LoadMassProportional,
    MarkerBodyMass,
    MarkerNodePosition,
    NodePoint2DSlope1,
    ObjectANCFCable2D,
)
from scipy.optimize import brentq

from ftfof.config import GRAVITY, FilmMechanics, FootMechanics
from ftfof.sim.bonds import BondLaw, contact_pressure
from ftfof.sim.foot import hold_film

esym = exu.symbolic
Real = esym.Real


@dataclass(frozen=True)
class FilmGrid:
    """The film's elements along the pad: node positions, element lengths and starts, and each
    node's pad area (its tributary length times the film's width)."""

    x_ref: np.ndarray  # node reference x, increasing from 0 to the pad's length
    length: np.ndarray  # element lengths
    start: np.ndarray  # element start x
    area: np.ndarray  # pad area per node
    pitch: float | None = None  # the element length of a uniform grid

    def element_at(self, x: float) -> int:
        """The element holding film x (the pad's end: the last element). A uniform grid finds it
        by floor division, as the simulator always has: a node whose x rounds below its element's
        start is held at the end of the element before it, the same point, and keeping it there
        keeps today's runs bit-identical. A graded grid: the last element starting at or before
        x."""
        last = self.length.size - 1
        if self.pitch is not None:
            return min(int(x // self.pitch + 1e-9), last)
        return min(int(np.searchsorted(self.start, x, side="right")) - 1, last)


def film_grid(
    pad_length: float, elements: int, width: float, grip: float, edge_element: float | None = None
) -> FilmGrid:
    """The film's elements: uniform, or graded with ``edge_element`` long ones over the grip, at
    the clamp edge, where the foot bends the film, and at the pad's end, where its last bonds let
    go (the detachment's jitter peaks there), longest in the pad's middle (docs/simulator.md,
    "Graded film elements")."""
    if edge_element is None:
        return _uniform_grid(pad_length, elements, width)
    return _graded_grid(pad_length, elements, width, grip, edge_element)


def _uniform_grid(pad_length: float, elements: int, width: float) -> FilmGrid:
    """Equal elements, every number as the simulator has always had it (bit-identical runs)."""
    x_ref = np.linspace(0.0, pad_length, elements + 1)
    dx = pad_length / elements
    area = np.full(elements + 1, width * dx)
    area[[0, -1]] /= 2
    return FilmGrid(x_ref, np.full(elements, dx), np.arange(elements) * dx, area, dx)


def _graded_grid(
    pad_length: float, elements: int, width: float, grip: float, edge_element: float
) -> FilmGrid:
    """The grip in equal elements no longer than ``edge_element`` (so it ends on a node), then
    the bonded pad from ``edge_element`` at either end, growing by one ratio per element toward
    its middle."""
    in_grip = max(math.ceil(grip / edge_element - 1e-9), 1) if grip > 0 else 0  # plate: none
    on_pad = elements - in_grip
    rest = pad_length - grip
    if on_pad < 1 or on_pad * edge_element >= rest * (1 - 1e-9):
        raise ValueError(
            f"a graded film of {elements} elements cannot start at {edge_element} m: the pad past"
            f" the grip takes {on_pad} elements for {rest} m"
        )
    k = np.arange(on_pad)
    steps = np.minimum(k, on_pad - 1 - k)  # elements from the nearer end of the pad
    pad = grip + edge_element * np.cumsum(_growth_ratio(steps, rest / edge_element) ** steps)
    pad[-1] = pad_length
    x_ref = np.concatenate([np.linspace(0.0, grip, in_grip + 1), pad])
    length = np.diff(x_ref)
    tributary = np.concatenate([[0.0], length]) + np.concatenate([length, [0.0]])
    return FilmGrid(x_ref, length, x_ref[:-1], width * tributary / 2)


def _growth_ratio(steps: np.ndarray, total: float) -> float:
    """The ratio q > 1 with sum(q ** steps) = ``total`` (the sum rises with q: one root)."""

    def excess(q: float) -> float:
        return float(np.sum(q**steps)) - total

    high = 2.0
    while excess(high) < 0:
        high *= 2
    return float(brentq(excess, 1.0, high, xtol=1e-14))


def _shared_law(mbs: Any, connectors: list[Any], law: Any) -> Any:
    """One symbolic spring-force law set on every connector; it must outlive the solve."""
    shared = CreateSymbolicUserFunction(
        mbs, law, "springForceUserFunction", itemTypeName="ObjectConnectorCartesianSpringDamper"
    )
    for obj in connectors:
        mbs.SetObjectParameter(obj, "springForceUserFunction", shared)
    return shared


def add_film(
    mbs: Any,
    film: FilmMechanics,
    grid: FilmGrid,
    foot_body: Any,
    foot: FootMechanics,
    origin: float = 0.0,
    gravity: tuple[float, float] = (0.0, -GRAVITY),
) -> tuple[list[Any], list[Any], Any]:
    """The film's nodes at ``origin + grid.x_ref`` on the wall (the foot's reference x is
    ``origin``), its elements under ``gravity``, held by the foot (:func:`ftfof.sim.foot.
    hold_film`); returns (nodes, elements, curvature-stop law). The platform's plate lies under
    gravity (-z); a wall has it along the film (-x)."""
    nodes = [
        mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[origin + x, 0.0, 1.0, 0.0]))
        for x in grid.x_ref
    ]
    elements = [
        mbs.AddObject(
            ObjectANCFCable2D(
                nodeNumbers=[nodes[i], nodes[i + 1]],
                length=float(grid.length[i]),
                massPerLength=film.mass_per_length,
                bendingStiffness=film.bending_stiffness,
                axialStiffness=film.axial_stiffness,
                bendingDamping=film.bending_damping,
                axialDamping=film.axial_damping,
                useReducedOrderIntegration=1,
            )
        )
        for i in range(grid.length.size)
    ]
    stop = CreateSymbolicUserFunction(
        mbs, _bending_moment(film), "bendingMomentUserFunction", itemTypeName="ObjectANCFCable2D"
    )
    for e in elements:
        mbs.AddLoad(
            LoadMassProportional(
                markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=e)),
                loadVector=[*gravity, 0.0],
            )
        )
    hold_film(mbs, foot, film, grid, nodes, elements, foot_body)
    return nodes, elements, stop


def _bending_moment(film: FilmMechanics) -> Any:
    """Linear bending (EI, damping) plus a curvature stop: past 1 / stop_radius the moment
    rises ``stop_stiffness`` times faster, so the film cannot be folded flat at no cost."""
    limit, gain = 1.0 / film.stop_radius, film.stop_stiffness

    def bending_moment(
        mbs,
        t,
        itemNumber,
        axialPositionNormalized,
        curvature,
        curvature_t,
        curvatureRef,
        bendingStiffness,
        bendingDamping,
        axialStrain,
        axialStrain_t,
        axialStrainRef,
    ):
        k = curvature - curvatureRef
        over = esym.max(esym.abs(k) - Real(limit), Real(0.0)) * esym.sign(k)
        return bendingStiffness * (k + Real(gain) * over) + bendingDamping * curvature_t

    return bending_moment


def add_bonds(
    mbs: Any,
    law: BondLaw,
    film_nodes: list[Any],
    x_ref: np.ndarray,
    area: np.ndarray,
    initial_pressure: float,
    plate_marker: Any,
) -> tuple[list[Any], Any]:
    """One bond connector per film node, bonded with the preload of ``initial_pressure``;
    returns (connectors, their shared symbolic force law, which must outlive the solve)."""
    phi0 = float(law.preload_factor(initial_pressure))
    connectors: list[Any] = []
    for i, node in enumerate(film_nodes):
        obj = mbs.AddObject(
            CartesianSpringDamper(
                markerNumbers=[plate_marker, mbs.AddMarker(MarkerNodePosition(nodeNumber=node))],
                stiffness=bond_stiffness(law, float(area[i])),
                damping=[0.0, phi0, 0.0],
                offset=[x_ref[i], 0.0, x_ref[i]],
            )
        )
        connectors.append(obj)
    return connectors, _shared_law(mbs, connectors, _bond_force(law))


def bond_law(mbs: Any, law: BondLaw) -> Any:
    """The bonds' symbolic force law on ``law``'s surface, set on no connector yet: a pad that
    moves to another surface mid-run takes it (it must outlive the solve)."""
    return _shared_law(mbs, [], _bond_force(law))


def bond_stiffness(law: BondLaw, area: float) -> list[float]:
    """A bond connector's stiffness parameter: [K_t A, K A, Kc A]."""
    return [law.shear_stiffness * area, law.stiffness * area, law.contact_stiffness * area]


def _bond_force(law: BondLaw) -> Any:
    """The bond connector's force law (:mod:`ftfof.sim.bonds`): the surface's friction and
    contact constants are baked in; the bond's and the slider's state come in through the
    connector's parameters. Exudyn's u is the markers' relative position less the offset, so the
    film's x on the plate is u[0] + offset[0], and the slider's stretch that less offset[2]."""
    w, hc, mu = law.contact_smoothing, law.hunt_crossley, law.friction
    none = Real(0.0)

    def bond_force(mbs, t, itemNumber, u, v, k, d, offset):
        # bonded (d[0] = 0): s (K_t A u_t, K A u_n), minus the contact when touching; broken
        # (d[0] = 1): the contact alone. Either way, touching, the slider's friction, clipped at
        # mu times the node's compressive force (a pressed bond's spring included). Exudyn
        # re-evaluates a subexpression wherever it is used, so each branch computes only what
        # its case needs
        touching = u[1] < none  # the contact pressure is exactly 0 otherwise
        contact = contact_pressure(u[1], v[1], k[2], w, hc, esym.max, esym.min)
        held = d[1] * k[1] * u[1]
        pressed = esym.IfThenElse(d[0], contact, contact - held)
        limit = mu * pressed
        stretch = k[0] * (u[0] + offset[0] - offset[2])  # the slider is as stiff as the bond
        friction = esym.max(esym.min(stretch, limit), -limit)
        fn = esym.IfThenElse(touching, -pressed, esym.IfThenElse(d[0], none, held))
        ft = esym.IfThenElse(
            touching,
            esym.IfThenElse(d[0], friction, d[1] * k[0] * u[0] + friction),
            esym.IfThenElse(d[0], none, d[1] * k[0] * u[0]),
        )
        return [ft, fn, 0]

    return bond_force
