"""The film's bend where the foot can crease it: curvature of the free span (docs/simulator.md).

What ``free_span_curvature`` measures, per recorded time: the largest curvature (1/m) of the film
centreline between the foot's clamp edge and the peel front, the first bonded node past the clamp.
The centreline is the ANCF cable's own cubic-Hermite interpolation of the node positions and
slopes; its geometric curvature |r' x r''| / |r'|^3 is evaluated at both ends and the middle of
every free element. The span is empty (curvature 0) when the node at the clamp edge is still
bonded, and there is no peel front once no node past the clamp is bonded.

Left out, on purpose:
- the clamped part: rigid with the foot's sole (:func:`clamp_pins` makes it so);
- the bonded part: it lies on the plate, and its cohesive zone bends less than the free span's
  root next to it;
- the film after the pad's first full release (the caller zeroes it): the flap flies free and its
  shape in flight and at landing is not converged in the node count.

The largest curvature sits at the clamp edge, where the foot bends the film: FTFOF's film limit
fc is about that bend. Measured this way the minimum bend radius moves by less than 10 % from
N = 40 to 80, and from 20 to 40 except where a strong pull squeezes the clamp edge's boundary
layer below one 2.5 mm element (the polynomial: -12 %); tests/sim/test_film.py.

Pins at the grip nodes alone leave the film a hinge at the clamp edge whose stiffness grows as
the elements shrink (the edge slope strayed 12 degrees from the sole at N = 20, 4 at N = 80), so
the last clamped element is pinned at four points: straight and rigid with the sole, the film
leaves the clamp tangent to it at every N.

The curvature stop (:func:`ftfof.sim.pad._bending_moment`) is a symbolic moment law that costs
+70 % run time on every element; :func:`arm_stops` lets the pre-step put it only on elements
bent past ARM / stop_radius, and take it off below DISARM / stop_radius.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from ftfof.config import Robot, Surface

Array = NDArray[np.float64]
XI = np.array([0.0, 0.5, 1.0])  # where each element's curvature is evaluated
ARM, DISARM = 0.5, 0.35  # an element's curvature stop is on from ARM / stop_radius to DISARM


def clamp_edge(x_ref: Array, grip: float) -> int:
    """Index of the node at the clamp edge: the first node at or past ``grip`` (at least 1)."""
    return max(int(np.searchsorted(x_ref, grip - 1e-9 * x_ref[-1])), 1)


def clamp_pins(x_ref: Array, grip: float) -> Array:
    """Film reference x of the points the foot pins: every node up to the clamp edge and two
    inner points of the last clamped element (four pins on a cubic hold it straight)."""
    edge = clamp_edge(x_ref, grip)
    a, b = x_ref[edge - 1], x_ref[edge]
    return np.concatenate([x_ref[: edge + 1], [a + (b - a) / 3, a + 2 * (b - a) / 3]])


def element_curvature(coords: Array, x_ref: Array) -> Array:
    """Curvature (1/m) at XI of every element: (T, n_nodes, 4) node coordinates -> (T, n-1, 3).

    ``coords`` are ANCF displacements (x, z, slope_x, slope_z) from the reference straight film
    (x_ref, 0, 1, 0), as Exudyn stores them.
    """
    pos = np.stack([x_ref + coords[..., 0], coords[..., 1]], axis=-1)
    slope = np.stack([1.0 + coords[..., 2], coords[..., 3]], axis=-1)
    L = np.diff(x_ref)[None, :, None, None]
    r0, r1 = pos[:, :-1, None], pos[:, 1:, None]
    d0, d1 = slope[:, :-1, None] * L, slope[:, 1:, None] * L
    xi = XI[None, None, :, None]
    # cubic Hermite r(xi) = h00 r0 + h10 d0 + h01 r1 + h11 d1, derivatives per unit length
    dr = (
        (6 * xi**2 - 6 * xi) * (r0 - r1) + (3 * xi**2 - 4 * xi + 1) * d0 + (3 * xi**2 - 2 * xi) * d1
    ) / L
    ddr = ((12 * xi - 6) * (r0 - r1) + (6 * xi - 4) * d0 + (6 * xi - 2) * d1) / L**2
    cross = dr[..., 0] * ddr[..., 1] - dr[..., 1] * ddr[..., 0]
    return np.abs(cross) / np.maximum(np.hypot(dr[..., 0], dr[..., 1]), 1e-12) ** 3


def free_span_curvature(coords: Array, x_ref: Array, edge: int, bonded: Array) -> Array:
    """Max curvature of the free span at each time: (T, n, 4) coordinates, (T, n) bonded -> (T,).

    The span runs over the elements from the clamp edge node ``edge`` to the first bonded node
    past it; 0 where that is empty or where no node past the clamp is bonded.
    """
    n = x_ref.size
    past = bonded[:, edge:]
    has_front = past.any(axis=1)
    front = edge + np.argmax(past, axis=1)  # first bonded node at or past the edge
    element = np.arange(n - 1)
    free = (element[None] >= edge) & (element[None] < front[:, None]) & has_front[:, None]
    out = np.zeros(len(bonded))
    peeling = np.flatnonzero(free.any(axis=1))  # the curvature is needed only while peeling
    if peeling.size:
        kappa = element_curvature(coords[peeling], x_ref).max(axis=2)
        out[peeling] = np.where(free[peeling], kappa, 0.0).max(axis=1)
    return out


@numba.njit(cache=True)
def arm_stops(
    q: Array,
    node_index: NDArray[np.int64],
    x_ref: Array,
    armed: NDArray[np.bool_],
    arm_at: float,
    disarm_at: float,
    changed: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """Arm the curvature stop of each element whose mean curvature (end-slope angle change over
    its length) passes ``arm_at``, disarm it below ``disarm_at``; lists the elements that changed
    in ``changed`` and returns how many. A pre-step function: state in the ODE2 vector ``q``."""
    n_changed = 0
    prev = np.arctan2(q[node_index[0] + 3], 1.0 + q[node_index[0] + 2])
    for i in range(1, node_index.size):
        j = node_index[i]
        angle = np.arctan2(q[j + 3], 1.0 + q[j + 2])
        turn = (angle - prev + np.pi) % (2 * np.pi) - np.pi
        prev = angle
        kappa = abs(turn) / (x_ref[i] - x_ref[i - 1])
        e = i - 1
        if (not armed[e] and kappa > arm_at) or (armed[e] and kappa < disarm_at):
            armed[e] = not armed[e]
            changed[n_changed] = e
            n_changed += 1
    return n_changed


def peel_root_radius(bending_stiffness: float, width: float, fracture_energy: float) -> float:
    """The film's bend radius at the root of a steady peel, sqrt(EI / (2 b G)).

    Elastica of the free arm: the energy balance at the root gives the root moment
    M = sqrt(2 EI b G), so the root curvature M / EI is set by the film and the adhesive alone,
    whatever the peel angle or trajectory.
    """
    return math.sqrt(bending_stiffness / (2.0 * width * fracture_energy))


def survival_energy(bending_stiffness: float, width: float, fc: float) -> float:
    """The largest fracture energy whose steady peel keeps the film at fc, EI / (2 b fc^2).

    A sharp-crack, quasi-static bound: the peel-root radius sqrt(EI / 2bG) does not depend on
    the path, so a film that survives its adhesive's peels at fc bounds the adhesive's G by
    this. The simulator's cohesive zone (an opening of millimetres) bends the film less than the
    sharp crack, its rate factor more (docs/decisions/0013-fracture-energy-cap.md).
    """
    return bending_stiffness / (2.0 * width * fc**2)


def clamp_edge_radius(bending_stiffness: float, pull: float, angle: float) -> float:
    """The film's bend radius at the clamp edge under ``pull`` at ``angle`` (rad) between the
    film's tangent in the clamp and the pull.

    Elastica of the free span between clamp and peel front: the moment at the clamp edge is
    sqrt(2 EI F (1 - cos phi)), so the curvature there is sqrt(2 F (1 - cos phi) / EI). It
    assumes a span much longer than sqrt(EI / F) (about 4 mm at 7 N for the 240 um film), which
    the peel's first millimetre is not: a bound's size, not the simulator's measure.
    """
    return math.sqrt(bending_stiffness / (2.0 * pull * (1.0 - math.cos(angle))))


def max_pull_angle(bending_stiffness: float, pull: float, fc: float) -> float:
    """The largest angle (rad) between film and ``pull`` at which the clamp edge keeps fc."""
    return math.acos(max(1.0 - bending_stiffness / (2.0 * pull * fc**2), -1.0))


@dataclass(frozen=True)
class FilmLimit:
    """The smallest film bend radius a trajectory may cause, fc, and the peel's own bend beside it.

    fc is a damage limit of the film (FTFOF §VI.A.3), and the film is as thick as fc lets it be,
    so fc is the rule. The peel-root radius is a diagnostic: a steady quasi-static peel bends the
    film that much at its root whatever the path, so where it is below fc only paths that load
    the film differently (a faster peel, another angle at the clamp) keep fc.
    """

    fc: float  # m, the robot's film limit
    peel_root: float  # m, sqrt(EI / (2 b G)) of this film on this surface

    @property
    def radius(self) -> float:
        return self.fc

    def as_dict(self) -> dict[str, float]:
        """For reports: lengths in m to the micrometre."""
        return {
            "limit": round(self.radius, 6),
            "fc": round(self.fc, 6),
            "peel_root_radius": round(self.peel_root, 6),
        }


def film_limit(robot: Robot, surface: Surface) -> FilmLimit:
    """The film safety limit of ``robot``'s film on ``surface``."""
    film = robot.platform.film
    root = peel_root_radius(film.bending_stiffness, film.width, surface.fracture_energy)
    return FilmLimit(robot.foot.film_min_bend_radius, root)
