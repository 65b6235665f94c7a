"""evaluate.slip_comparison: the scenario's climb under each controller, into the metrics."""

from __future__ import annotations

import pytest

import ftfof.pipeline.slip as climbs
from ftfof.climb.outcome import CONTROLLERS
from ftfof.climb.surface import SurfaceSwitch
from ftfof.config import LEG_NAMES
from ftfof.config.validate import parse_params
from ftfof.errors import ParamsError
from ftfof.pipeline.bench import baseline_trajectories, context_of
from ftfof.report import run_metrics


def test_the_comparison_climbs_the_scenario_once_per_controller(params, tmp_path, monkeypatch):
    seen = []

    def compare(spec, out_dir, title, workers, label):
        seen.append(spec)
        row = {"slip_distance": 2e-3, "slip_path": 5e-3, "max_slip_velocity": 7e-3}
        row |= {"mu_error": 0.05, "adhesion_error": None, "estimated_slips": 3.0}
        row |= {"fell": False, "fall": ""}
        return {c: {**row, "steps_done": 8} for c in CONTROLLERS}

    monkeypatch.setattr(climbs, "compare_controllers", compare)
    ctx = context_of(params)
    scenario = params.evaluate.slip_scenario
    trajectory = baseline_trajectories(params, ctx)[scenario.trajectory]
    table = climbs.slip_comparison(*climbs.slip_scenario_spec(params, ctx, trajectory), tmp_path)
    (spec,) = seen
    foot = LEG_NAMES.index(scenario.foot)
    switch = SurfaceSwitch(foot, scenario.time, params.surfaces[scenario.surface])
    assert spec.switch == switch and spec.name == "slip_eps_bezier"
    assert set(table) == set(CONTROLLERS)
    figures = {"slip_distance": 2e-3, "slip_path": 5e-3, "max_slip_velocity": 7e-3}
    figures |= {"mu_error": 0.05, "adhesion_error": None, "estimated_slips": 3.0}
    assert table["both"] == {**figures, "fell": False}
    metrics = run_metrics.evaluate({"table": {}, "fidelity": {}, "slip": table, "seconds": 1.0})
    assert metrics["slip.both.slip_distance"] == 2e-3 and metrics["slip.none.fell"] == 0.0
    assert metrics["slip.both.mu_error"] == 0.05 and "slip.both.adhesion_error" not in metrics


def test_a_scenario_on_an_unknown_surface_is_one_line_naming_its_key(params_dict):
    params_dict["evaluate"]["slip_scenario"] = {"foot": "FL", "time": 4.0, "surface": "ice"}
    with pytest.raises(ParamsError) as err:
        parse_params(params_dict)
    assert "evaluate.slip_scenario.surface" in str(err.value) and "\n" not in str(err.value)


def test_a_scenario_time_outside_the_climb_is_refused_naming_its_key(params_dict):
    params_dict["evaluate"]["slip_scenario"]["time"] = 99.0
    params = parse_params(params_dict)
    ctx = context_of(params)
    trajectory = baseline_trajectories(params, ctx)["eps_bezier"]
    outside = r"evaluate\.slip_scenario\.time: 99 s is outside the climb"
    with pytest.raises(ParamsError, match=outside):
        climbs.slip_scenario_spec(params, ctx, trajectory)
