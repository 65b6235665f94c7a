"""The payload margin's bisection (on a cheap stand-in for the climbs), the loaded climb's spec,
and the command's refusals."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from ftfof.study.payload import Bisection
from stages.cli import app
from tests.conftest import write_params


def search(limit: float | None, ceiling: float = 0.4, resolution: float = 0.01) -> Bisection:
    """The bisection run to its end against a robot that climbs with up to ``limit`` kg added
    (None: it falls even unloaded)."""
    b = Bisection(ceiling, resolution)
    while (mass := b.next()) is not None:
        b.tell(mass, limit is not None and mass <= limit)
    return b


@pytest.mark.parametrize("limit", [0.0, 0.004, 0.0123, 0.1, 0.2, 0.3999])
def test_the_margin_is_found_to_the_resolution_from_below(limit):
    b = search(limit)
    report = b.report()
    assert report["climbs_unloaded"]
    assert report["payload"] <= limit < report["fell_with"]
    assert report["fell_with"] - report["payload"] <= 0.01
    # unloaded, the ceiling, then halvings of 0.4 down to 10 g: ceil(log2(40)) = 6
    assert len(b.tries) == 2 + 6
    assert [t["mass"] for t in report["tries"][:2]] == [0.0, 0.4]


def test_a_trajectory_that_climbs_at_the_ceiling_stops_there():
    report = search(1.0).report()
    assert report["payload"] == 0.4 and report["fell_with"] is None and len(report["tries"]) == 2


def test_a_trajectory_that_falls_unloaded_has_no_margin_after_one_climb():
    report = search(None).report()
    assert not report["climbs_unloaded"] and report["payload"] == 0.0
    assert report["tries"] == [{"mass": 0.0, "climbed": False}]


def test_the_loaded_spec_adds_the_mass_to_the_trunk_only(params):
    from ftfof.pipeline.bench import baseline_trajectories, context_of
    from ftfof.pipeline.climb import spec_for
    from ftfof.study.payload import with_payload

    ctx = context_of(params)
    trajectory = baseline_trajectories(params, ctx)["polynomial"]
    spec = spec_for(params, ctx, "polynomial", trajectory, None)
    loaded = with_payload(spec, 0.125)
    assert loaded.name == "polynomial+125g"
    assert loaded.robot.climber.trunk_mass == pytest.approx(spec.robot.climber.trunk_mass + 0.125)
    unchanged = loaded.robot.model_copy(update={"climber": spec.robot.climber})
    assert unchanged == spec.robot and loaded.trajectory is spec.trajectory


def test_a_robot_without_a_climber_is_refused_in_one_line_writing_nothing(params_dict, tmp_path):
    params_dict["robots"][params_dict["robot"]]["climber"] = None
    params_dict["robots"][params_dict["robot"]]["proof"] = None  # the climber's demand
    path = write_params(tmp_path / "params.yaml", params_dict)
    report, figure = tmp_path / "payload.json", tmp_path / "payload.png"
    args = ["study", "payload", "-p", str(path), "--report", str(report), "--figure", str(figure)]
    result = CliRunner().invoke(app, args)
    assert result.exit_code != 0
    assert "has no climber block" in result.output and len(result.output.strip().splitlines()) == 1
    assert not report.exists() and not figure.exists()


def test_a_resolution_at_or_above_the_ceiling_is_refused(params_dict, tmp_path):
    params_dict["study"]["payload"] = {"ceiling": 0.05, "resolution": 0.05}
    path = write_params(tmp_path / "params.yaml", params_dict)
    result = CliRunner().invoke(app, ["study", "payload", "-p", str(path)])
    assert result.exit_code != 0 and "must be below the ceiling" in result.output
