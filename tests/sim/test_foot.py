"""The foot: the plate's parts in the params, its ankle's rest and stop, its film grid."""

import math

import exudyn as exu
import numpy as np
import pytest
from exudyn.itemInterface import (
    CoordinateSpringDamper,
    MarkerNodeCoordinate,
    MarkerNodeRigid,
    NodePointGround,
    NodeRigidBody2D,
    ObjectRigidBody2D,
    Torque,
)
from pydantic import ValidationError

from ftfof.config import FootMechanics, Params
from ftfof.sim.foot import ankle_law, free_span_start, grip_of
from ftfof.sim.pad import film_grid

PLATE = {
    "model": "plate",
    "mass": 0.05,
    "inertia": 5.3e-5,
    "ankle_height": 0.015,
    "grip_length": 0.005,
    "ankle_stiffness": 0.05,
    "ankle_damping": 0.001,
    "backing": {
        "modulus": 1.0e6,
        "thickness": 0.001,
        "poisson": 0.45,
        "damping_ratio": 0.2,
        "source": "a test's foam backing",
    },
    "ankle_range": (-0.5, 0.1),
}


def test_a_plate_needs_its_backing_and_its_range():
    FootMechanics.model_validate(PLATE)
    for change, words in (
        ({"backing": None}, "needs foot.backing"),
        ({"ankle_range": None}, "needs foot.backing and foot.ankle_range"),
        ({"ankle_range": (0.1, 0.3)}, "must hold 0"),
    ):
        with pytest.raises(ValidationError, match=words):
            FootMechanics.model_validate({**PLATE, **change})


def test_the_plate_rests_toe_down_at_the_droop_angle(params_dict: dict):
    robot = params_dict["robots"]["mst_m3f"]
    robot["platform"]["foot"] = {**PLATE}
    plate = Params.model_validate(params_dict).selected_robot
    hs, lf = plate.foot.droop_height, plate.foot.pad_length
    assert plate.ankle_rest_angle == pytest.approx(-math.asin(hs / lf))
    robot["platform"]["foot"] = {**PLATE, "model": "grip", "backing": None, "ankle_range": None}
    assert Params.model_validate(params_dict).selected_robot.ankle_rest_angle == 0.0


def test_the_plate_backs_the_whole_film_from_its_heel():
    foot = FootMechanics.model_validate(PLATE)
    x_ref = np.linspace(0.0, 0.05, 41)
    assert grip_of(foot, 0.05) == 0.0
    assert free_span_start(foot, x_ref) == 0
    grip = foot.model_copy(update={"model": "grip", "backing": None})
    assert grip_of(grip, 0.05) == 0.005
    assert free_span_start(grip, x_ref) == 4


def test_a_graded_grid_without_a_grip_starts_at_the_heel():
    grid = film_grid(0.05, 30, 0.02, 0.0, 0.0005)
    assert grid.x_ref[0] == 0.0 and grid.x_ref[-1] == pytest.approx(0.05)
    assert grid.length.min() == pytest.approx(0.0005)
    assert (grid.length > 0).all()
    assert grid.area.sum() == pytest.approx(0.05 * 0.02)


def _ankle_angle(torque: float, foot: FootMechanics, rest: float) -> float:
    """The foot's angle under a steady ``torque`` on the ankle law, settled."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddNode(NodePointGround())
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, 0.0, 0.0]))
    mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=0.05, inertia=foot.inertia))
    for i in (0, 1):
        mbs.AddObject(
            CoordinateSpringDamper(
                markerNumbers=[
                    mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0)),
                    mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=i)),
                ],
                stiffness=1e4,
                damping=10.0,
            )
        )
    ankle = mbs.AddObject(
        CoordinateSpringDamper(
            markerNumbers=[
                mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0)),
                mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=2)),
            ],
            stiffness=foot.ankle_stiffness,
            damping=foot.ankle_damping * 20,
        )
    )
    keep = ankle_law(mbs, ankle, foot, rest)
    mbs.AddLoad(Torque(markerNumber=mbs.AddMarker(MarkerNodeRigid(nodeNumber=node)),
                       loadVector=[0.0, 0.0, torque]))  # fmt: skip
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = 3.0
    settings.timeIntegration.numberOfSteps = 3000
    settings.timeIntegration.verboseMode = 0
    exu.SolveDynamic(mbs, settings)
    del keep
    return float(mbs.GetNodeOutput(node, exu.OutputVariableType.Coordinates)[2])


def test_the_ankle_rests_at_its_angle_and_stops_at_its_range():
    foot = FootMechanics.model_validate(PLATE)
    k, (low, high) = foot.ankle_stiffness, foot.ankle_range
    rest = -0.1
    assert _ankle_angle(0.0, foot, rest) == pytest.approx(rest, abs=1e-4)
    inside = 0.005  # N m: turns it 0.1 rad, within the range
    assert _ankle_angle(inside, foot, rest) == pytest.approx(rest + inside / k, abs=1e-4)
    # a torque that would turn a free spring 2 rad past the stop ends just past it
    for torque, stop in ((k * (high - rest + 2.0), high), (-k * (rest - low + 2.0), low)):
        angle = _ankle_angle(torque, foot, rest)
        past = 2.0 * k / (k + foot.ankle_stop_stiffness)
        assert angle == pytest.approx(stop + math.copysign(past, stop), rel=1e-3)
