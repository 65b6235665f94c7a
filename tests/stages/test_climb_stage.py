"""`ftfof climb`: the whole robot on the wall from the command line, and what it refuses."""

from __future__ import annotations

import json

import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from stages.cli import app
from tests.conftest import PUBLISHED_M3F, ROOT, cli_args, write_params

runner = CliRunner()
PARAMS = ROOT / "params.yaml"


def test_one_trajectory_at_a_time(tmp_path):
    args = cli_args("climb", PARAMS, baseline="polynomial", out_dir=tmp_path / "out")
    result = runner.invoke(app, [*args, "--optimum"])
    assert result.exit_code == 2 and "exactly one of" in result.stderr
    assert not (tmp_path / "out").exists()


def test_points_the_robot_cannot_run_are_refused_naming_the_rule(tmp_path):
    X = PUBLISHED_M3F.copy()
    X[7] = -0.01  # P4z ten millimetres into the wall
    points = ",".join(f"{v:g}" for v in X)
    result = runner.invoke(app, cli_args("climb", PARAMS, points=points, out_dir=tmp_path / "o"))
    assert result.exit_code == 2 and "cannot run them" in result.stderr
    assert not (tmp_path / "o").exists()


def test_a_robot_without_a_climber_cannot_climb(tmp_path, params_dict):
    del params_dict["robots"]["mst_m3f"]["climber"]
    params_dict["robots"]["mst_m3f"]["proof"] = None  # the proof pull is the climber's demand
    params = write_params(tmp_path / "params.yaml", params_dict)
    result = runner.invoke(
        app, cli_args("climb", params, baseline="polynomial", out_dir=tmp_path / "o")
    )
    assert result.exit_code == 2 and "has no climber block" in result.stderr


def test_a_leg_that_cannot_stand_at_p0_is_refused_before_anything_runs(tmp_path, params_dict):
    """MST-Q's hip 20 mm ahead of P0 (its preset's first estimate) puts P0 at a hip pitch of
    -1.32 rad, past its -1.0 limit: no trajectory can start there, which the robot's context
    says at once (the joint rule alone would have drawn the sampler's whole budget)."""
    params_dict["robot"] = "mst_q"
    params_dict["robots"]["mst_q"]["leg"]["hip"]["x"] = 0.02
    params = write_params(tmp_path / "params.yaml", params_dict)
    result = runner.invoke(
        app, cli_args("climb", params, baseline="eps_bezier", out_dir=tmp_path / "o")
    )
    assert result.exit_code == 2 and "cannot hold the foot at P0" in result.stderr
    assert not (tmp_path / "o").exists()


@pytest.mark.integration
def test_a_one_step_climb_writes_its_channels_imu_metrics_and_traces(tmp_path, params_dict):
    params_dict["climb"]["steps"] = 1
    params = write_params(tmp_path / "params.yaml", params_dict)
    out = tmp_path / "out"
    result = runner.invoke(app, cli_args("climb", params, baseline="cycloidal", out_dir=out))
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "cycloidal.json",
        "cycloidal.parquet",
        "cycloidal.png",
        "cycloidal_imu.parquet",
        "cycloidal_side.png",
    ]
    doc = json.loads((out / "cycloidal.json").read_text())
    assert doc["summary"]["fell"] is False and doc["summary"]["steps_done"] == 1
    (step,) = doc["steps"]
    assert step["release"] == "" and step["jitter"] > 0 and step["peak_pull"] > 1.0
    # a servo past its limit is named with its joint (the plate's first hind peel loads the other
    # hind hip past its estimated 1.5 N m: decision 0028)
    assert step["torque_ratio"] > 0
    assert (step["torque"] == "") == (step["torque_ratio"] <= 1), step["torque"]
    assert step["torque_ratio"] <= 1 or " needs " in step["torque"]
    assert step["film"] == ""  # the cycloid's first peel keeps fc
    assert (
        step["min_bend_radius"]
        >= 0.9 * params_dict["robots"]["mst_m3f"]["foot"]["film_min_bend_radius"]
    )
    channels = pq.read_table(out / "cycloidal.parquet")
    assert {"t", "body_x", "Fz_FL", "bonds_HR", "torque_FL1"} <= set(channels.column_names)
    imu = pq.read_table(out / "cycloidal_imu.parquet")
    assert imu.column_names == ["t", "acc_x", "acc_z", "gyro", "acc"]


def test_a_proof_pull_above_the_pads_strength_is_refused_before_anything_runs(
    tmp_path, params_dict
):
    """20 times the fore foot's demand is 132 N, past the acrylic pad's whole strength sigma A
    (66.7 N): no landing could hold it, and the search would refuse every trajectory."""
    params_dict["robots"]["mst_m3f"]["proof"]["safety_factor"] = 20.0
    params = write_params(tmp_path / "params.yaml", params_dict)
    result = runner.invoke(
        app, cli_args("climb", params, baseline="polynomial", out_dir=tmp_path / "o")
    )
    assert result.exit_code == 2 and "proof.safety_factor" in result.stderr
    assert "above the pad's strength" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and not (tmp_path / "o").exists()
