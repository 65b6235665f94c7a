"""The climbing robot on a vertical wall as one Exudyn system (docs/climb.md).

Planar, sagittal: Exudyn x is up the wall, Exudyn y is our z (out of the wall), gravity along -x.
Items:

- one KinematicTree: the trunk on a floating base (x, z, pitch: three joints without control)
  and four legs of three revolute joints each, servo-controlled by the tree's joint PD (the
  platform's joint gains) toward targets the solver loop sets every step;
- per leg: the foot, a rigid body on the ankle link through a spring-damper whose rotation is
  the passive ankle (and whose x, z are the optional foot mount, MST-Q's support rack), and
  :mod:`ftfof.sim.pad`'s film and bonds on a wall patch, the film held by the foot as on the
  platform (:mod:`ftfof.sim.foot`);
- per wall patch: a point mass on two stiff springs, the platform's force sensor, so the pad's
  force on the wall is read as on the platform (the wall itself is rigid behind it).

Left out: everything outside the sagittal plane (a leg's abduction, roll and yaw of the trunk,
left and right legs are two legs on one hip), the legs' cables, the servos' own dynamics beyond
their PD gains.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    CoordinateSpringDamper,
    LoadMassProportional,
    MarkerBodyMass,
    MarkerKinematicTreeRigid,
    MarkerNodeCoordinate,
    MarkerNodePosition,
    MarkerNodeRigid,
    MassPoint2D,
    NodePoint2D,
    NodePointGround,
    NodeRigidBody2D,
    ObjectConnectorRigidBodySpringDamper,
    ObjectKinematicTree,
    ObjectRigidBody2D,
    SensorKinematicTree,
)

import ftfof.config as config
from ftfof.climb.gait import LEGS, Gait
from ftfof.climb.legs import SagittalChain
from ftfof.climb.surface import PadSwitch, SurfaceSwitch
from ftfof.demand import leg_masses
from ftfof.sim.bonds import BondLaw
from ftfof.sim.foot import ankle_joint_law, free_span_start, grip_of
from ftfof.sim.joint_leg import ATTACH_DAMPING, ATTACH_STIFFNESS, tree_node
from ftfof.sim.pad import FilmGrid, add_bonds, add_film, film_grid
from ftfof.sim.padstate import PadParts
from ftfof.trajectory.piecewise import PiecewiseQuintic

BASE = 3  # the trunk's floating coordinates in the tree: x, z, pitch
TRUNK_LINK = 2
JOINTS = 3  # per leg


@dataclass(frozen=True)
class ClimbSpec:
    """What one climb needs, as a picklable value."""

    name: str  # the trajectory's label
    trajectory: PiecewiseQuintic  # the swing, P0 = (0, 0), over [0, T3]
    robot: config.Robot
    surface: config.Surface
    platform: config.Platform  # the force sensor under each wall patch and the press protocol
    solver: config.Solver
    climb: config.Climb
    seed: int  # the IMU's noise
    switch: SurfaceSwitch | None = None  # climb.surface_change, resolved (ftfof.climb.surface)


@dataclass
class Climber:
    """Handles into the built system that the solver loop and post-processing need."""

    sc: Any
    mbs: Any
    spec: ClimbSpec
    chain: SagittalChain
    gait: Gait
    law: BondLaw
    tree: Any
    tree_node: Any
    pads: list[PadParts]
    feet: list[Any]  # foot nodes
    patch_springs: list[tuple[Any, Any]]  # (x, z) force-sensor springs of each wall patch
    clamp_edge: int
    imu_sensor: Any  # the trunk's acceleration from the solver (the IMU test's reference)
    initial_pressure: float  # Pa over each pad
    q0: np.ndarray  # the tree's initial coordinates
    keep: list[Any] = field(default_factory=list)  # symbolic functions must outlive the solve
    switch: PadSwitch | None = None  # the pad that changes surface mid-climb, if one does

    @property
    def hips(self) -> np.ndarray:
        return self.gait.hips


def build(spec: ClimbSpec, chain: SagittalChain, gait: Gait, law: BondLaw) -> Climber:
    """Assemble the robot standing on the wall with every pad bonded (not yet solved)."""
    foot = spec.robot.platform.foot
    grid = _film_grid(spec)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddNode(NodePointGround())
    g0 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    feet_x = gait.initial_feet()
    q0 = _start_pose(chain, gait, feet_x)
    tree, tree_node = _tree(mbs, spec, chain, gait, q0, float(chain.hip[1]))
    initial_pressure = spec.robot.pre_pressure / float(grid.area.sum())
    legs = [
        _leg(mbs, spec, law, grid, (tree, g0), leg, float(feet_x[leg]), initial_pressure)
        for leg in range(LEGS)
    ]
    pads = [pad for pad, _, _, _ in legs]
    switch = None
    if spec.switch is not None:
        other = BondLaw.from_surface(spec.switch.surface, spec.solver.contact_smoothing)
        switch = PadSwitch(mbs, spec.switch, other, pads[spec.switch.leg])
    imu = mbs.AddSensor(
        SensorKinematicTree(
            objectNumber=tree,
            linkNumber=TRUNK_LINK,
            outputVariableType=exu.OutputVariableType.Acceleration,
            storeInternal=True,
            writeToFile=False,
        )
    )
    mbs.Assemble()
    return Climber(
        sc=sc,
        mbs=mbs,
        spec=spec,
        chain=chain,
        gait=gait,
        law=law,
        tree=tree,
        tree_node=tree_node,
        pads=pads,
        feet=[foot_node for _, foot_node, _, _ in legs],
        patch_springs=[spring for _, _, spring, _ in legs],
        clamp_edge=free_span_start(foot, grid.x_ref),
        imu_sensor=imu,
        initial_pressure=initial_pressure,
        q0=q0,
        keep=[item for *_, keep in legs for item in keep],
        switch=switch,
    )


def _film_grid(spec: ClimbSpec) -> FilmGrid:
    """Each pad's film nodes along the pad, held by the foot's grip."""
    mech = spec.robot.platform
    pad = spec.robot.foot.pad_length
    grip = grip_of(mech.foot, pad)
    return film_grid(pad, spec.solver.nodes, mech.film.width, grip, spec.solver.edge_element)


def _start_pose(chain: SagittalChain, gait: Gait, feet_x: np.ndarray) -> np.ndarray:
    """The tree's initial coordinates: the base at rest, each leg's joints on its foot's start."""
    q0 = np.zeros(BASE + LEGS * JOINTS)
    theta0 = chain.leg.inverse(np.stack([feet_x - gait.hips + chain.hip[0], np.zeros(LEGS)], 1))
    if not np.all(np.isfinite(theta0)):
        raise ValueError("a foot's start is outside its leg's reach")
    q0[BASE:] = theta0.ravel()
    return q0


def _leg(
    mbs: Any,
    spec: ClimbSpec,
    law: BondLaw,
    grid: FilmGrid,
    anchors: tuple[Any, Any],
    leg: int,
    xf: float,
    initial_pressure: float,
) -> tuple[PadParts, Any, tuple[Any, Any], list[Any]]:
    """One leg's wall patch, foot, ankle, film and bonds, its foot at ``xf`` on the wall
    (``anchors``: the tree and the ground's marker): the pad's parts, the foot node, the patch's
    sensor springs, and the symbolic functions to keep."""
    tree, g0 = anchors
    foot = spec.robot.platform.foot
    gravity = (-config.GRAVITY, 0.0)
    patch, springs = _wall_patch(mbs, g0, xf, spec.platform.sensor)
    foot_node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[xf, foot.ankle_height, 0]))
    foot_body = mbs.AddObject(
        ObjectRigidBody2D(nodeNumber=foot_node, mass=foot.mass, inertia=foot.inertia)
    )
    mbs.AddLoad(
        LoadMassProportional(
            markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=foot_body)),
            loadVector=[*gravity, 0.0],
        )
    )
    film = spec.robot.platform.film
    nodes, elements, stop = add_film(mbs, film, grid, foot_body, foot, origin=xf, gravity=gravity)
    keep = []
    ankle = _ankle(mbs, spec, tree, leg, foot_node)
    if foot.model == "plate":
        keep.append(ankle_joint_law(mbs, ankle, foot, spec.robot.ankle_rest_angle))
    patch_marker = mbs.AddMarker(MarkerNodePosition(nodeNumber=patch))
    connectors, law_fn = add_bonds(
        mbs, law, nodes, grid.x_ref, grid.area, initial_pressure, patch_marker
    )
    keep += [stop, law_fn]
    pad = PadParts(nodes, elements, stop, connectors, patch, grid.x_ref, grid.area)
    return pad, foot_node, springs, keep


def _wall_patch(mbs: Any, g0: Any, xf: float, sensor: config.Sensor) -> tuple[Any, tuple[Any, Any]]:
    """A wall patch at ``xf``: the force sensor's plate on its x and z springs to the ground."""
    patch = mbs.AddNode(NodePoint2D(referenceCoordinates=[xf, 0.0]))
    mbs.AddObject(MassPoint2D(nodeNumber=patch, mass=sensor.plate_mass))
    springs = tuple(
        mbs.AddObject(
            CoordinateSpringDamper(
                markerNumbers=[
                    g0,
                    mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=patch, coordinate=i)),
                ],
                stiffness=sensor.stiffness,
                damping=sensor.damping,
            )
        )
        for i in (0, 1)
    )
    return patch, springs


def _ankle(mbs: Any, spec: ClimbSpec, tree: Any, leg: int, foot_node: Any) -> Any:
    """The foot on ``leg``'s ankle link: a spring-damper whose rotation is the passive ankle and
    whose x, z are the foot mount (stiff where the robot has none)."""
    foot = spec.robot.platform.foot
    climber = spec.robot.climber
    assert climber is not None
    mount = climber.foot_mount_stiffness
    kx = mount.x if mount else ATTACH_STIFFNESS
    kz = mount.z if mount else ATTACH_STIFFNESS
    return mbs.AddObject(
        ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[
                mbs.AddMarker(
                    MarkerKinematicTreeRigid(
                        objectNumber=tree,
                        linkNumber=BASE + leg * JOINTS + 2,
                        localPosition=[0.0, 0.0, 0.0],
                    )
                ),
                mbs.AddMarker(MarkerNodeRigid(nodeNumber=foot_node)),
            ],
            stiffness=np.diag([kx, kz, ATTACH_STIFFNESS, 0, 0, foot.ankle_stiffness]).tolist(),
            damping=np.diag([ATTACH_DAMPING] * 3 + [0.0, 0.0, foot.ankle_damping]).tolist(),
        )
    )


def _tree(
    mbs: Any, spec: ClimbSpec, chain: SagittalChain, gait: Gait, q0: np.ndarray, hip_z: float
) -> tuple[Any, Any]:
    """The trunk on its floating base and the four servo-driven legs, as one kinematic tree."""
    robot = spec.robot
    climber = robot.climber
    assert climber is not None
    mech = robot.platform
    l1, l2 = chain.links
    kp, kd = mech.joint_gains
    n = len(q0)
    node = tree_node(mbs, q0)
    zero = [0.0, 0.0, 0.0]
    types = [exu.JointType.PrismaticX, exu.JointType.PrismaticY, exu.JointType.RevoluteZ]
    parents = [-1, 0, 1]
    offsets = [zero, zero, zero]
    coms = [zero, zero, zero]
    masses = [1e-6, 1e-6, climber.trunk_mass]
    inertias = [np.zeros((3, 3))] * 2 + [np.diag([0.0, 0.0, climber.trunk_inertia])]
    link_masses = leg_masses(robot)
    for leg in range(LEGS):
        first = len(types)
        types += [exu.JointType.RevoluteZ] * JOINTS
        parents += [TRUNK_LINK, first, first + 1]
        offsets += [[float(gait.hips[leg]), 0.0, 0.0], [l1, 0.0, 0.0], [l2, 0.0, 0.0]]
        coms += [[l1 / 2, 0.0, 0.0], [l2 / 2, 0.0, 0.0], zero]
        masses += list(link_masses)
        inertias += [
            np.diag([0.0, 0.0, link_masses[0] * l1**2 / 12]),
            np.diag([0.0, 0.0, link_masses[1] * l2**2 / 12]),
            np.diag([0.0, 0.0, 1e-7]),
        ]
    tree = mbs.AddObject(
        ObjectKinematicTree(
            nodeNumber=node,
            gravity=[-config.GRAVITY, 0.0, 0.0],
            baseOffset=[0.0, hip_z, 0.0],
            jointTypes=types,
            linkParents=parents,
            jointTransformations=exu.Matrix3DList([np.eye(3)] * n),
            jointOffsets=exu.Vector3DList(offsets),
            linkInertiasCOM=exu.Matrix3DList(inertias),
            linkCOMs=exu.Vector3DList(coms),
            linkMasses=masses,
            jointPControlVector=[0.0] * BASE + [kp] * (n - BASE),
            jointDControlVector=[0.0] * BASE + [kd] * (n - BASE),
            jointPositionOffsetVector=q0.tolist(),
            jointVelocityOffsetVector=[0.0] * n,
        )
    )
    return tree, node
