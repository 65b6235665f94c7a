"""A stance pad's hold: the fore foot's demand on the wall, on the platform (issue 51)."""

import pytest

from ftfof.config import GRAVITY
from ftfof.demand import fore_foot_demand, robot_mass
from ftfof.sim.hold import at_rest, hold_test
from tests.sim.helpers import bench


def test_the_fore_foots_demand_is_the_partners_press_and_the_weights_tip(params):
    robot = params.selected_robot
    tip = robot_mass(robot) * GRAVITY * robot.leg.hip.z / robot.climber.hip_spacing
    assert fore_foot_demand(robot) == pytest.approx(robot.pre_pressure + tip)
    assert 1.0 < tip < 2.5  # MST-M3F: 0.81 kg, hips 40 mm off the wall, 0.2 m apart


def test_a_stance_pad_holds_a_light_pull_and_lets_a_heavy_one_peel_it(params):
    """Pressed at a, then pulled at its ankle: half the fore foot's demand holds for 2 s with the
    whole pad bonded and the ankle still within a tenth of a millimetre; twice the demand peels
    the plate about its toe. (The calibrated plate holds 5.8 N, below the 6.6 N demand:
    docs/decisions/0028.)"""
    robot = params.selected_robot
    spec = bench(params).spec("hold", 0, at_rest(1.0))
    demand = fore_foot_demand(robot)
    light = hold_test(spec, 0.5 * demand, ramp=0.1, hold=2.0)
    assert light.held and light.bonded == 1.0
    assert light.pull == pytest.approx(0.5 * demand, rel=0.05)
    assert 0.0 <= light.rise < 1e-4
    heavy = hold_test(spec, 2.0 * demand, ramp=0.1, hold=0.5)
    assert not heavy.held and heavy.rise > 1e-3
