"""What the bond law implies for a slip test's estimate, and the preset an estimate gives back."""

from __future__ import annotations

import pytest

from ftfof.identify.estimate import Estimate
from ftfof.sim.bonds import BondLaw
from ftfof.sim.identified import (
    PROTOCOL,
    identified_preset,
    law_of,
    preset_of,
    quasi_static,
    quasi_static_block,
    rate_law,
    truth,
)
from ftfof.sim.slip import adhesion_truth
from ftfof.sim.spec import Bench


def _law(surface, params) -> BondLaw:
    return BondLaw.from_surface(surface, params.acquire.solver.contact_smoothing)


def test_the_truth_is_the_preset_friction_and_the_laws_adhesion(params):
    robot, surface = params.selected_robot, params.surfaces["glass"]
    law = _law(surface, params)
    out = truth(law, robot)
    assert out.mu == surface.friction
    static = adhesion_truth(law, robot.pre_pressure, robot.pad_area)
    assert static == pytest.approx(
        float(law.preload_factor(robot.pre_pressure / robot.pad_area))
        * law.shear_strength
        * robot.pad_area
    )
    assert out.adhesion == pytest.approx(law.drag_rate_factor(PROTOCOL.speed) * static)
    assert out.adhesion > static


@pytest.mark.parametrize("pull_off", [None, 4.0e4])
def test_an_identified_preset_gives_back_the_estimate(params, pull_off):
    robot, surface = params.selected_robot, params.surfaces["glass"]
    est = Estimate(0.456789, 12.5)
    block = identified_preset(_law(surface, params), robot, surface, "log.csv", est, pull_off)
    assert block["friction"] == 0.4568 and "log.csv" in block["note"]
    if pull_off is not None:
        assert block["strength"] == pull_off
    again = truth(_law(surface.model_copy(update=block), params), robot, speed=0.0)
    assert again.mu == pytest.approx(est.mu, rel=1e-3)
    assert again.adhesion == pytest.approx(est.adhesion, rel=1e-3)  # F_adh,0


def test_two_drag_speeds_give_back_the_rate_law(params):
    robot, law = params.selected_robot, _law(params.surfaces["glass"], params)
    static = adhesion_truth(law, robot.pre_pressure, robot.pad_area)
    drags = {v: adhesion_truth(law, robot.pre_pressure, robot.pad_area, v) for v in (1e-3, 4e-3)}
    got = rate_law(law, static, drags)
    assert got.exponent == pytest.approx(law.rate_exponent, rel=1e-9)
    assert got.speed == pytest.approx(law.rate_speed, rel=1e-9)
    with pytest.raises(ValueError, match="rise with the speed"):
        rate_law(law, static, {1e-3: static, 4e-3: 2 * static})


def _bench(params, name: str) -> Bench:
    surface = params.surfaces[name]
    return Bench(params.selected_robot, surface, params.platform, params.acquire, params.base.seed)


def test_the_benchs_law_is_its_surfaces_at_the_acquisitions_smoothing(params):
    on = _bench(params, "glass")
    assert law_of(on) == _law(params.surfaces["glass"], params)
    est = Estimate(0.4, 12.5)
    block = identified_preset(law_of(on), on.robot, on.surface, "log.csv", est, 4.0e4)
    assert preset_of(on, "log.csv", est, 4.0e4) == block


@pytest.mark.parametrize("simulated", [True, False])
def test_the_quasi_static_block_takes_the_estimate_back_to_no_rate(params, simulated):
    on, est = _bench(params, "glass"), Estimate(0.4, 12.5)
    law, robot = law_of(on), on.robot
    block = quasi_static_block(on, est, simulated)
    assert block["estimate"] == quasi_static(law, 12.5, PROTOCOL.speed) < 12.5
    assert block["speed"] == PROTOCOL.speed
    static = adhesion_truth(law, robot.pre_pressure, robot.pad_area)
    assert block["truth"] == (static if simulated else None)
