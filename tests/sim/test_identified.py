"""What the bond law implies for a slip test's estimate, and the preset an estimate gives back."""

from __future__ import annotations

import pytest

from ftfof.identify.estimate import Estimate
from ftfof.sim.bonds import BondLaw
from ftfof.sim.identified import identified_preset, truth
from ftfof.sim.slip import adhesion_truth


def _law(surface, params) -> BondLaw:
    return BondLaw.from_surface(surface, params.acquire.solver.contact_smoothing)


def test_the_truth_is_the_preset_friction_and_the_laws_adhesion(params):
    robot, surface = params.selected_robot, params.surfaces["glass"]
    law = _law(surface, params)
    out = truth(law, robot)
    assert out.mu == surface.friction
    assert out.adhesion == adhesion_truth(law, robot.pre_pressure, robot.pad_area) > 0


@pytest.mark.parametrize("pull_off", [None, 4.0e4])
def test_an_identified_preset_gives_back_the_estimate(params, pull_off):
    robot, surface = params.selected_robot, params.surfaces["glass"]
    est = Estimate(0.456789, 12.5)
    block = identified_preset(_law(surface, params), robot, surface, "log.csv", est, pull_off)
    assert block["friction"] == 0.4568 and "log.csv" in block["note"]
    if pull_off is not None:
        assert block["strength"] == pull_off
    again = truth(_law(surface.model_copy(update=block), params), robot)
    assert again.mu == pytest.approx(est.mu, rel=1e-3)
    assert again.adhesion == pytest.approx(est.adhesion, rel=1e-3)
