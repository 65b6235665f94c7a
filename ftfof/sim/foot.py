"""The foot that holds the film, and its passive ankle (docs/simulator.md, "The foot").

Two feet, chosen by ``foot.model``:

- ``grip``: a rigid foot clamps the film's first ``grip_length`` (pinned at every node inside
  the grip, the last clamped element held straight with the sole: :func:`ftfof.sim.film.
  clamp_pins`); the rest of the pad lies free ahead of it and peels as a film does.
- ``plate``: a rigid plate the pad's length backs the whole film through a compliant layer, one
  normal spring E A / t and one shear spring G A / t per film node (the node's pad area A). A
  heel pull turns the plate about its toe, so the pad lets go as FTFOF §VI.A.3's rigid element
  of length lf does (ld = lf - sqrt(lf^2 - hd^2)), and a landing press reaches the whole pad
  through the plate. The springs act along the wall's axes, not the plate's: at the 10 degrees
  of the plate at hd they mix the normal and shear stiffness by 2 %.

The ankle is a rotational spring between the leg's last link and the foot. The plate's rests
toe down in the air at the robot's droop angle (Robot.ankle_rest_angle) and stops at
``foot.ankle_range``: past it the stop adds ``ankle_stop_stiffness``. A stop at flat (the
range's upper end 0) makes the ankle one-way: free to turn toe down, so the heel peels about the
toe, and stiff at flat, so a press at the heel spreads over the whole pad instead of levering the
toe up.
"""

from __future__ import annotations

import math
from typing import Any

import exudyn as exu
import numpy as np
from exudyn.advancedUtilities import CreateSymbolicUserFunction
from exudyn.itemInterface import (
    CartesianSpringDamper,
    MarkerBodyPosition,
    MarkerNodePosition,
    ObjectJointRevolute2D,
)

from ftfof.config import FilmMechanics, FootMechanics
from ftfof.sim import film as film_shape

esym = exu.symbolic
Real = esym.Real


def hold_film(
    mbs: Any,
    foot: FootMechanics,
    film: FilmMechanics,
    grid: Any,
    nodes: list[Any],
    elements: list[Any],
    foot_body: Any,
) -> None:
    """Join the film to the foot: the grip's clamp pins, or the plate's backing springs."""
    if foot.model == "plate":
        _back(mbs, foot, film, grid, nodes, foot_body)
    else:
        _clamp(mbs, grid, elements, foot_body, foot.ankle_height, grip_of(foot, grid.x_ref[-1]))


def grip_of(foot: FootMechanics, pad_length: float) -> float:
    """The film length the foot holds rigidly at the heel: the grip, or none under a plate."""
    return 0.0 if foot.model == "plate" else min(foot.grip_length, pad_length)


def free_span_start(foot: FootMechanics, x_ref: np.ndarray) -> int:
    """The film node from which the film's bend is measured: the grip's clamp edge, or the
    plate's heel (the whole film is backed, so its bend is where it leaves the plate)."""
    if foot.model == "plate":
        return 0
    return film_shape.clamp_edge(x_ref, grip_of(foot, float(x_ref[-1])))


def _clamp(
    mbs: Any, grid: Any, elements: list[Any], foot_body: Any, ankle_height: float, grip: float
) -> None:
    for x in film_shape.clamp_pins(grid.x_ref, grip):
        e = grid.element_at(x)
        on_film = mbs.AddMarker(
            MarkerBodyPosition(bodyNumber=elements[e], localPosition=[x - grid.start[e], 0.0, 0.0])
        )
        on_foot = mbs.AddMarker(
            MarkerBodyPosition(bodyNumber=foot_body, localPosition=[x, -ankle_height, 0.0])
        )
        mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[on_foot, on_film]))


def _back(
    mbs: Any,
    foot: FootMechanics,
    film: FilmMechanics,
    grid: Any,
    nodes: list[Any],
    foot_body: Any,
) -> None:
    backing = foot.backing
    assert backing is not None
    for x, area, node in zip(grid.x_ref, grid.area, nodes, strict=True):
        k_n = backing.modulus * area / backing.thickness
        k_t = backing.shear_modulus * area / backing.thickness
        mass = film.mass_per_length * area / film.width
        mbs.AddObject(
            CartesianSpringDamper(
                markerNumbers=[
                    mbs.AddMarker(
                        MarkerBodyPosition(
                            bodyNumber=foot_body, localPosition=[x, -foot.ankle_height, 0.0]
                        )
                    ),
                    mbs.AddMarker(MarkerNodePosition(nodeNumber=node)),
                ],
                stiffness=[k_t, k_n, 0.0],
                damping=[2 * backing.damping_ratio * math.sqrt(k * mass) for k in (k_t, k_n)]
                + [0.0],
            )
        )


def backing_stiffness(foot: FootMechanics, pad_area: float) -> float:
    """The whole backing's normal stiffness, N/m (infinite for the grip foot)."""
    if foot.backing is None or foot.model != "plate":
        return math.inf
    return foot.backing.modulus * pad_area / foot.backing.thickness


def pressed_area(foot: FootMechanics, film: FilmMechanics, pad_length: float) -> float:
    """The pad area a press reaches through the foot: the grip's, or the whole plate's."""
    return (pad_length if foot.model == "plate" else grip_of(foot, pad_length)) * film.width


def _stop(angle: Any, foot: FootMechanics) -> Any:
    """How far ``angle`` is past the ankle's range (0 inside it)."""
    if foot.ankle_range is None:
        return Real(0.0)
    low, high = foot.ankle_range
    return esym.max(angle - Real(high), Real(0.0)) + esym.min(angle - Real(low), Real(0.0))


def ankle_law(mbs: Any, connector: Any, foot: FootMechanics, rest: float) -> Any:
    """The ankle's moment on a coordinate spring over the foot's rotation (the platform's
    lumped leg, whose leg keeps its orientation); returns the law, which must outlive the
    solve."""
    stop = Real(foot.ankle_stop_stiffness)

    def ankle(mbs, t, itemNumber, u, v, k, d, offset):
        return k * (u - Real(rest)) + stop * _stop(u, foot) + d * v

    return _set(mbs, connector, ankle, "springForceUserFunction")


def ankle_joint_law(mbs: Any, connector: Any, foot: FootMechanics, rest: float) -> Any:
    """The same moment on a rigid-body spring-damper from the leg's last link to the foot
    (its translations: the diagonal springs of the connector); returns the law."""
    stop = Real(foot.ankle_stop_stiffness)

    def ankle(mbs, t, itemNumber, u, rot, v, w, k, d, rotJ0, rotJ1, offset):
        turn = rot[2] - Real(rest)
        moment = k[5, 5] * turn + stop * _stop(rot[2], foot) + d[5, 5] * w[2]
        return [
            k[0, 0] * u[0] + d[0, 0] * v[0],
            k[1, 1] * u[1] + d[1, 1] * v[1],
            k[2, 2] * u[2] + d[2, 2] * v[2],
            Real(0.0),
            Real(0.0),
            moment,
        ]

    return _set(mbs, connector, ankle, "springForceTorqueUserFunction")


def _set(mbs: Any, connector: Any, law: Any, name: str) -> Any:
    sym = CreateSymbolicUserFunction(mbs, law, name, connector)
    mbs.SetObjectParameter(connector, name, sym)
    return sym
