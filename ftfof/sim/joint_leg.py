"""Joint-level leg (``acquire.leg_model: joints``): an Exudyn KinematicTree driven by joint PD.

Tree: two prismatic joints carry the robot body on its mounts (their PD gains *are* the mount
stiffness and damping, the body mass sits on the second), then hip, knee and an ankle servo
(RevoluteZ) tracking the inverse kinematics of the commanded foot motion, updated every step.
The foot body hangs on the ankle link through a single marker (docs/simulator.md: many tree
markers are slow) with a rigid-body spring-damper whose rotational stiffness about z is the
passive ankle. Planar (``planar3``) legs only. About 5-7x slower than the lumped leg: it exists
to check the lumped model, not for bulk data.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    MarkerKinematicTreeRigid,
    MarkerNodeRigid,
    NodeGenericODE2,
    ObjectConnectorRigidBodySpringDamper,
    ObjectKinematicTree,
    SensorKinematicTree,
)

import ftfof.config as config
from ftfof.demand import SERVO_LINK_MASS
from ftfof.errors import SimulationError
from ftfof.kinematics.legs import Leg, build_leg
from ftfof.sim.foot import ankle_joint_law
from ftfof.sim.spec import SampleSpec

ATTACH_STIFFNESS = 2e5  # N/m, foot-to-ankle-link attachment (stiff against the leg's compliance)
ATTACH_DAMPING = 20.0


def tree_node(mbs: Any, q0: np.ndarray) -> Any:
    """The node of a KinematicTree's joint coordinates, starting at ``q0`` at rest."""
    n = len(q0)
    return mbs.AddNode(
        NodeGenericODE2(
            numberOfODE2Coordinates=n,
            referenceCoordinates=[0.0] * n,
            initialCoordinates=q0.tolist(),
            initialCoordinates_t=[0.0] * n,
        )
    )


def attach_joint_leg(p: Any, foot_node: Any, g0: Any) -> Any:
    """Build the tree, attach the foot, register the per-step target update; returns the IMU."""
    spec = p.spec
    if not isinstance(spec.leg, config.PlanarLeg):
        raise SimulationError(spec.key, "the joint-level leg model supports planar3 legs only")
    mbs = p.mbs
    targets = _targets(p, build_leg(spec.leg))
    theta0, _ = targets(0.0)
    if not np.all(np.isfinite(theta0)):
        raise SimulationError(spec.key, "the start pose is outside the leg's reach")
    q0 = np.concatenate([[0.0, 0.0], theta0])
    tree = _tree(mbs, spec, tree_node(mbs, q0), q0)
    _attach_foot(p, tree, foot_node)
    p.leg_update = _updater(mbs, tree, targets, len(q0))
    return mbs.AddSensor(
        SensorKinematicTree(
            objectNumber=tree,
            linkNumber=1,
            outputVariableType=exu.OutputVariableType.Acceleration,
            storeInternal=True,
            writeToFile=False,
        )
    )


Targets = Callable[[float], tuple[np.ndarray, np.ndarray]]


def _targets(p: Any, leg: Leg) -> Targets:
    """The joint angles and rates (hip, knee, ankle) that put the foot on the commanded motion,
    less the press depth, at a time; NaN angles outside the leg's reach."""
    traj, t0 = p.spec.trajectory, p.spec.trajectory_start

    def targets(t: float) -> tuple[np.ndarray, np.ndarray]:
        s = traj.sample(np.array([t - t0]))
        p_cmd = s.position[0, 0] - np.array([0.0, p.press_depth.Evaluate()])
        theta = leg.inverse(p_cmd)
        rates = np.linalg.lstsq(leg.jacobian(theta)[:, :2], s.velocity[0, 0], rcond=None)[0]
        return theta, np.array([rates[0], rates[1], -rates[0] - rates[1]])

    return targets


def _tree(mbs: Any, spec: SampleSpec, node: Any, q0: np.ndarray) -> Any:
    """The KinematicTree: body on its mounts (two prismatic joints), hip, knee, ankle servo."""
    mech = spec.mechanics
    l1, l2 = spec.leg.links
    kp, kd = mech.joint_gains
    body = mech.body
    n = len(q0)
    eye = np.eye(3).tolist()
    zero = [0.0, 0.0, 0.0]
    inertia = (
        [np.zeros((3, 3)).tolist()] * 2
        + [(np.diag([0.0, 0.0, mech.link_mass * length**2 / 12]).tolist()) for length in (l1, l2)]
        + [np.diag([0.0, 0.0, 1e-7]).tolist()]
    )
    return mbs.AddObject(
        ObjectKinematicTree(
            nodeNumber=node,
            baseOffset=[spec.leg.hip.x, spec.leg.hip.z, 0.0],
            jointTypes=[exu.JointType.PrismaticX, exu.JointType.PrismaticY]
            + [exu.JointType.RevoluteZ] * 3,
            linkParents=[-1, 0, 1, 2, 3],
            jointTransformations=exu.Matrix3DList([np.array(eye)] * n),
            jointOffsets=exu.Vector3DList([zero, zero, zero, [l1, 0.0, 0.0], [l2, 0.0, 0.0]]),
            linkInertiasCOM=exu.Matrix3DList([np.array(m) for m in inertia]),
            linkCOMs=exu.Vector3DList([zero, zero, [l1 / 2, 0.0, 0.0], [l2 / 2, 0.0, 0.0], zero]),
            linkMasses=[1e-6, body.mass, mech.link_mass, mech.link_mass, SERVO_LINK_MASS],
            jointPControlVector=[body.mount_stiffness.x, body.mount_stiffness.z, kp, kp, kp],
            jointDControlVector=[body.mount_damping.x, body.mount_damping.z, kd, kd, kd],
            jointPositionOffsetVector=q0.tolist(),
            jointVelocityOffsetVector=[0.0] * n,
        )
    )


def _attach_foot(p: Any, tree: Any, foot_node: Any) -> None:
    """The foot on the ankle link: stiff in translation, the passive ankle's spring about z."""
    mbs, foot = p.mbs, p.spec.mechanics.foot
    k_attach = [ATTACH_STIFFNESS] * 3 + [0.0, 0.0, foot.ankle_stiffness]
    d_attach = [ATTACH_DAMPING] * 3 + [0.0, 0.0, foot.ankle_damping]
    ankle = mbs.AddObject(
        ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[
                mbs.AddMarker(
                    MarkerKinematicTreeRigid(
                        objectNumber=tree, linkNumber=4, localPosition=[0.0, 0.0, 0.0]
                    )
                ),
                mbs.AddMarker(MarkerNodeRigid(nodeNumber=foot_node)),
            ],
            stiffness=np.diag(k_attach).tolist(),
            damping=np.diag(d_attach).tolist(),
        )
    )
    if foot.model == "plate":
        p.keep.append(ankle_joint_law(mbs, ankle, foot, p.spec.ankle_rest))


def _updater(mbs: Any, tree: Any, targets: Targets, n: int) -> Callable[[float], None]:
    """The per-step update of the tree's joint targets; the last reachable ones held outside
    the leg's reach."""
    offsets = np.zeros(n)
    rates = np.zeros(n)

    def update(t: float) -> None:
        theta, dtheta = targets(t)
        if np.all(np.isfinite(theta)):
            offsets[2:] = theta
            rates[2:] = dtheta
        mbs.SetObjectParameter(tree, "jointPositionOffsetVector", offsets.tolist())
        mbs.SetObjectParameter(tree, "jointVelocityOffsetVector", rates.tolist())

    return update
