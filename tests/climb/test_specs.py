"""The climbs built from config sections (:mod:`ftfof.climb.specs`)."""

from __future__ import annotations

from ftfof.climb.outcome import CONTROLLERS
from ftfof.climb.specs import controller_specs, scenario_climb, slip_table, slip_title
from tests.climb.helpers import spec_of


def test_each_controller_climbs_the_same_spec_under_its_own_name(params):
    spec = spec_of(params, "eps_bezier")
    specs = controller_specs(spec)
    assert list(specs) == list(CONTROLLERS)
    for controller, one in specs.items():
        assert one.name == f"{spec.name}.{controller}" and one.climb.controller == controller
        assert one.trajectory is spec.trajectory and one.switch == spec.switch


def test_the_scenario_changes_only_the_climbs_surface_change(params):
    scenario = params.evaluate.slip_scenario
    climb = scenario_climb(scenario, params.climb)
    change = climb.surface_change
    assert (change.foot, change.time, change.surface) == (
        scenario.foot,
        scenario.time,
        scenario.surface,
    )
    assert climb.model_dump(exclude={"surface_change"}) == params.climb.model_dump(
        exclude={"surface_change"}
    )
    assert slip_title("r", "glass", scenario).startswith(f"r on glass: {scenario.trajectory}, ")


def test_the_slip_table_keeps_the_slip_figures_of_each_row():
    row = {"slip_distance": 1.0, "slip_path": 2.0, "max_slip_velocity": 3.0, "fell": True}
    row |= {"mu_error": 0.1, "adhesion_error": None, "estimated_slips": 4.0}
    table = slip_table({"none": {**row, "steps_done": 8, "fall": "x"}})
    assert table == {"none": row}
