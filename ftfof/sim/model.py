"""The force-acquisition platform as an Exudyn multibody system (FTFOF §IV.A; docs/simulator.md).

Planar: Exudyn x is along the wall, Exudyn y is our z (normal to the plate). Items:

- adhesion plate: a point mass on two stiff spring-dampers, the 3-axis force sensor (x, z); the
  x spring's offset is the carriage of the linear module, moved to the landing point once the
  photoelectric switch sees the foot detached (a named symbolic variable holds the switch time);
- robot body: a point mass on compliant mounts (the other feet on the wall) carrying the IMU;
- lumped leg: x/z spring-dampers from the body to the ankle whose rest offset *is* the commanded
  trajectory (a symbolic piecewise quintic, exact velocity for the damper) minus the press depth;
- foot: a rigid body on a passive ankle spring holding the film (:mod:`ftfof.sim.foot`: a grip
  clamping its first ``grip_length``, or a plate backing all of it);
- the pad (:mod:`ftfof.sim.pad`): the ANCF film on the plate ahead of the foot and one cohesive
  bond connector per film node; a sensor per film node records its coordinates for
  :mod:`ftfof.sim.film`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

import exudyn as exu
import numpy as np
from exudyn.advancedUtilities import CreateSymbolicUserFunction
from exudyn.itemInterface import (
    CoordinateSpringDamper,
    LoadMassProportional,
    MarkerBodyMass,
    MarkerNodeCoordinate,
    MarkerNodePosition,
    MassPoint2D,
    NodePoint2D,
    NodePointGround,
    NodeRigidBody2D,
    ObjectRigidBody2D,
    SensorNode,
    SensorObject,
)

from ftfof.config import GRAVITY, FilmMechanics, FootMechanics, Sensor
from ftfof.sim.bonds import BondLaw
from ftfof.sim.foot import ankle_law, backing_stiffness, free_span_start, grip_of, pressed_area
from ftfof.sim.pad import add_bonds, add_film, film_grid
from ftfof.sim.padstate import PadParts
from ftfof.sim.spec import SampleSpec

esym = exu.symbolic
Real = esym.Real
STORE = {"storeInternal": True, "writeToFile": False}  # sensors keep their data in memory


@dataclass
class Platform:
    """Handles into a built system that the solver loop and post-processing need."""

    sc: Any
    mbs: Any
    spec: SampleSpec
    law: BondLaw
    x_ref: np.ndarray  # film node reference x
    area: np.ndarray  # pad area per bond
    film_nodes: list[Any]
    clamp_edge: int  # index of the film node at the clamp edge
    film_sensors: list[Any]  # node coordinates (x, z, slope_x, slope_z) per film node
    film_elements: list[Any]
    bend_stop: Any  # the curvature-stop moment law, set on an element while it is armed
    bonds: list[Any]
    plate_node: Any
    foot_node: Any
    sensors: dict[str, Any]
    switch_time: Any  # esym named Real
    press_depth: Any  # esym named Real
    series_stiffness: float  # estimate of the press path stiffness, N/m
    keep: list[Any] = field(default_factory=list)  # symbolic functions must outlive the solve
    leg_update: Callable[[float], None] | None = None  # per-step joint targets (joint-level leg)

    def pad_parts(self) -> PadParts:
        return PadParts(
            self.film_nodes,
            self.film_elements,
            self.bend_stop,
            self.bonds,
            self.plate_node,
            self.x_ref,
            self.area,
        )

    @property
    def initial_pressure(self) -> float:
        """The reset presses the whole pad with the pre-pressure spread over its area."""
        return self.spec.pre_pressure / float(self.area.sum())


def _coord(mbs: Any, node: Any, i: int) -> Any:
    return mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=i))


def _uf(p: Platform, obj: Any, fn: Any) -> None:
    sym = CreateSymbolicUserFunction(p.mbs, fn, "springForceUserFunction", obj)
    p.keep.append(sym)
    p.mbs.SetObjectParameter(obj, "springForceUserFunction", sym)


def _min_jerk(u: Any) -> Any:
    return u * u * u * (Real(10.0) - Real(15.0) * u + Real(6.0) * u * u)


def _min_jerk_rate(u: Any) -> Any:
    return Real(30.0) * u * u * (Real(1.0) - u) * (Real(1.0) - u)


def build(spec: SampleSpec, law: BondLaw) -> Platform:
    """Assemble the platform for one sample (not yet solved)."""
    m = spec.mechanics
    film, foot = m.film, m.foot
    pad = spec.pad_length
    grip = grip_of(foot, pad)
    grid = film_grid(pad, spec.solver.nodes, film.width, grip, spec.solver.edge_element)
    x_ref, area = grid.x_ref, grid.area
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddNode(NodePointGround())
    g0 = _coord(mbs, ground, 0)
    plate, sensor_x, sensor_z = _plate_on_sensor(mbs, g0, spec.platform.sensor)
    plate_pos = mbs.AddMarker(MarkerNodePosition(nodeNumber=plate))
    foot_node, foot_body = _foot_on_ankle(mbs, foot)

    # the film lying on the plate, held by the foot (the grip's clamp or the plate's backing)
    film_nodes, elements, stop = add_film(mbs, film, grid, foot_body, foot)

    p = Platform(
        sc=sc,
        mbs=mbs,
        spec=spec,
        law=law,
        x_ref=x_ref,
        area=area,
        film_nodes=film_nodes,
        clamp_edge=free_span_start(foot, x_ref),
        film_sensors=[],
        film_elements=elements,
        bend_stop=stop,
        bonds=[],
        plate_node=plate,
        foot_node=foot_node,
        sensors={},
        switch_time=Real("t_switch", 1e9),
        keep=[stop],
        press_depth=Real("press_depth", 0.0),
        series_stiffness=_series_stiffness(spec, law, area),
    )
    _carriage(p, sensor_x, spec)
    body_acc = _leg(p, g0, foot_node)
    p.bonds, bond_force = add_bonds(
        mbs, law, film_nodes, x_ref, area, p.initial_pressure, plate_pos
    )
    p.keep.append(bond_force)
    p.sensors = _sensors(p, sensor_x, sensor_z, body_acc)
    coords = exu.OutputVariableType.Coordinates
    p.film_sensors = [
        mbs.AddSensor(SensorNode(nodeNumber=node, outputVariableType=coords, **STORE))
        for node in film_nodes
    ]
    mbs.Assemble()
    return p


def _plate_on_sensor(mbs: Any, g0: Any, sensor: Sensor) -> tuple[Any, Any, Any]:
    """The adhesion plate, a point mass on the force sensor's x and z spring-dampers; returns
    the plate's node and the two springs."""
    plate = mbs.AddNode(NodePoint2D(referenceCoordinates=[0.0, 0.0]))
    mbs.AddObject(MassPoint2D(nodeNumber=plate, mass=sensor.plate_mass))
    springs = tuple(
        mbs.AddObject(
            CoordinateSpringDamper(
                markerNumbers=[g0, _coord(mbs, plate, axis)],
                stiffness=sensor.stiffness,
                damping=sensor.damping,
            )
        )
        for axis in (0, 1)
    )
    return plate, *springs


def _foot_on_ankle(mbs: Any, foot: FootMechanics) -> tuple[Any, Any]:
    """The foot, a rigid body at the ankle's height under gravity; returns its node and body."""
    foot_node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, foot.ankle_height, 0.0]))
    foot_body = mbs.AddObject(
        ObjectRigidBody2D(nodeNumber=foot_node, mass=foot.mass, inertia=foot.inertia)
    )
    mbs.AddLoad(
        LoadMassProportional(
            markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=foot_body)),
            loadVector=[0.0, -GRAVITY, 0.0],
        )
    )
    return foot_node, foot_body


def _leg(p: Platform, g0: Any, foot_node: Any) -> Any:
    """The leg model the spec names, between the body and the foot; returns the IMU sensor."""
    if p.spec.leg_model == "joints":
        from ftfof.sim.joint_leg import attach_joint_leg

        return attach_joint_leg(p, foot_node, g0)
    return _lumped_leg(p, g0, foot_node)


def _sensors(p: Platform, sensor_x: Any, sensor_z: Any, body_acc: Any) -> dict[str, Any]:
    """The force sensor's readings, the IMU, and the plate's and the foot's motion."""
    mbs, out = p.mbs, exu.OutputVariableType
    return {
        "Fx": mbs.AddSensor(
            SensorObject(objectNumber=sensor_x, outputVariableType=out.Force, **STORE)
        ),
        "Fz": mbs.AddSensor(
            SensorObject(objectNumber=sensor_z, outputVariableType=out.Force, **STORE)
        ),
        "body_acc": body_acc,
        # with the sensor forces, the plate's acceleration gives the pad-plate interface force
        "plate_acc": mbs.AddSensor(
            SensorNode(nodeNumber=p.plate_node, outputVariableType=out.Acceleration, **STORE)
        ),
        "plate": mbs.AddSensor(
            SensorNode(nodeNumber=p.plate_node, outputVariableType=out.Displacement, **STORE)
        ),
        "foot": mbs.AddSensor(
            SensorNode(nodeNumber=p.foot_node, outputVariableType=out.Position, **STORE)
        ),
    }


def _series_stiffness(spec: SampleSpec, law: BondLaw, area: np.ndarray) -> float:
    """Stiffness of the press path leg -> foot (its backing) -> the contact it presses ->
    sensor -> body mounts."""
    m = spec.mechanics
    parts = (
        m.leg_stiffness.z,
        m.body.mount_stiffness.z,
        spec.platform.sensor.stiffness,
        *pad_stiffnesses(law, m.foot, m.film, spec.pad_length),
    )
    return in_series(parts)


def pad_stiffnesses(
    law: BondLaw, foot: FootMechanics, film: FilmMechanics, pad_length: float
) -> tuple[float, float]:
    """The pressed pad's contact and its foot's backing (N/m): the press path's part that every
    foot pressing a pad shares, the platform's and the climbing robot's."""
    return (
        law.contact_stiffness * pressed_area(foot, film, pad_length),
        backing_stiffness(foot, pad_length * film.width),
    )


def in_series(parts: Iterable[float]) -> float:
    """Springs in series (N/m), summed in the order given: the press loops' gain divides by it,
    so an order kept keeps their floats."""
    return 1.0 / sum(1.0 / k for k in parts)


def _carriage(p: Platform, sensor_x: Any, spec: SampleSpec) -> None:
    """Sensor x spring whose ground point moves with the linear module after the switch."""
    move = spec.landing[0]
    dur = spec.platform.protocol.carriage_time
    ts = p.switch_time

    def sensor_force(mbs, t, itemNumber, u, v, k, d, offset):
        s = esym.min(esym.max((t - ts) / dur, Real(0.0)), Real(1.0))
        return k * (u - move * _min_jerk(s)) + d * (v - move * _min_jerk_rate(s) / dur)

    _uf(p, sensor_x, sensor_force)


def body_on_mounts(p: Platform, g0: Any) -> tuple[Any, Any, Any]:
    """The robot body (IMU) as a point mass on its mount springs; returns (x, z) markers, sensor."""
    mbs, body_m = p.mbs, p.spec.mechanics.body
    hip = p.spec.leg.hip
    body = mbs.AddNode(NodePoint2D(referenceCoordinates=[hip.x, hip.z]))
    mbs.AddObject(MassPoint2D(nodeNumber=body, mass=body_m.mass))
    bx, bz = _coord(mbs, body, 0), _coord(mbs, body, 1)
    for marker, k, d in (
        (bx, body_m.mount_stiffness.x, body_m.mount_damping.x),
        (bz, body_m.mount_stiffness.z, body_m.mount_damping.z),
    ):
        mbs.AddObject(CoordinateSpringDamper(markerNumbers=[g0, marker], stiffness=k, damping=d))
    acc = exu.OutputVariableType.Acceleration
    sensor = mbs.AddSensor(SensorNode(nodeNumber=body, outputVariableType=acc, **STORE))
    return bx, bz, sensor


def _lumped_leg(p: Platform, g0: Any, foot_node: Any) -> Any:
    """Leg springs whose rest offset is the commanded foot motion relative to the body."""
    mbs, spec = p.mbs, p.spec
    body_x, body_z, sensor = body_on_mounts(p, g0)
    traj = spec.trajectory.shifted(spec.trajectory_start)
    legs = (
        (0, body_x, spec.mechanics.leg_stiffness.x, spec.mechanics.leg_damping.x),
        (1, body_z, spec.mechanics.leg_stiffness.z, spec.mechanics.leg_damping.z),
    )
    for dim, body_marker, k, d in legs:
        obj = mbs.AddObject(
            CoordinateSpringDamper(
                markerNumbers=[body_marker, _coord(mbs, foot_node, dim)], stiffness=k, damping=d
            )
        )
        _uf(p, obj, _leg_force(traj, dim, p.press_depth if dim == 1 else Real(0.0)))
    foot = spec.mechanics.foot
    ankle = mbs.AddObject(  # passive ankle: the leg keeps its orientation, the foot turns on it
        CoordinateSpringDamper(
            markerNumbers=[g0, _coord(mbs, foot_node, 2)],
            stiffness=foot.ankle_stiffness,
            damping=foot.ankle_damping,
        )
    )
    if foot.model == "plate":
        p.keep.append(ankle_law(mbs, ankle, foot, spec.ankle_rest))
    return sensor


def _leg_force(traj: Any, dim: int, press: Any) -> Any:
    """Spring-damper force toward the commanded coordinate, with its exact velocity."""

    def leg_force(mbs, t, itemNumber, u, v, k, d, offset):
        target = traj.symbolic(t, esym, dim) - press
        rate = traj.symbolic(t, esym, dim, 1)
        return k * (u - target) + d * (v - rate)

    return leg_force
