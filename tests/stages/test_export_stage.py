"""`ftfof export`: the optimum, a front row or a baseline for the robot's controller, in CSV with
a metadata header, JSON or a ROS JointTrajectory's YAML, its joint angles the leg's inverse
kinematics of the foot path."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
import yaml
from typer.testing import CliRunner

from ftfof.kinematics.legs import build_leg
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.params_file import load_params
from stages.cli import app
from tests.conftest import cli_args

pytestmark = pytest.mark.integration
runner = CliRunner()


def _export(evaluated, tmp_path, name: str, fmt: str, **source):
    work, uri, _, evaluate_args = evaluated
    params = evaluate_args[evaluate_args.index("-p") + 1]
    out = tmp_path / name
    args = cli_args(
        "export",
        params,
        optimize=work / "polish" / "optimize",
        metrics=work / "metrics.json",
        format=fmt,
        out=out,
        **source,
    )
    result = runner.invoke(app, args, env={"MLFLOW_TRACKING_URI": uri})
    assert result.exit_code == 0, result.output
    return out, load_params(Path(params))


def _csv(path):
    lines = path.read_text().splitlines()
    meta = dict(line[2:].split(": ", 1) for line in lines if line.startswith("# "))
    body = [line for line in lines if not line.startswith("#")]
    return meta, body[0].split(","), np.loadtxt(body[1:], delimiter=",")


def test_the_optimum_as_csv_carries_its_provenance_and_reaches_its_foot_path(evaluated, tmp_path):
    out, params = _export(evaluated, tmp_path, "optimum.csv", "csv")
    meta, header, table = _csv(out)
    ctx = context_of(params)
    metrics = json.loads((evaluated[0] / "metrics.json").read_text())
    assert meta["robot"] == ctx.name and meta["trajectory"] == "optimum"
    assert int(meta["front_row"]) == metrics["optimum_front_row"]
    assert meta["simulated.peak_pull"] == str(metrics["table"]["optimum"]["peak_pull"])
    assert len(meta["models_digest"]) == 16 and meta["units.q"] == "rad"
    assert header[:3] == ["t [s]", "x [m]", "z [m]"]
    leg = build_leg(ctx.robot.leg)
    np.testing.assert_allclose(leg.forward(table[:, 5:8]), table[:, 1:3], atol=1e-9)
    rate = params.evaluate.export_rate_hz
    np.testing.assert_allclose(np.diff(table[:, 0]), 1 / rate, rtol=1e-9)


def test_a_front_row_as_a_ros_joint_trajectory(evaluated, tmp_path):
    work = evaluated[0]
    front = pq.read_table(work / "polish" / "optimize" / "front.parquet").to_pandas()
    row, (out, params) = _first_runnable(evaluated, tmp_path, front.row.tolist()[::-1])
    message = yaml.safe_load(out.read_text())
    assert message["joint_names"] == ["q1", "q2", "q3"]
    assert message["header"]["frame_id"].endswith("_foot_start")
    points = message["points"]
    times = [p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"] for p in points]
    assert np.all(np.diff(times) > 0) and len(points[0]["positions"]) == 3
    assert f"# front_row: {row}" in out.read_text()
    ctx = context_of(params)
    X = front.set_index("row").loc[row, [c for c in front.columns if c[0] == "P"]]
    s = ctx.policy.sample(X.to_numpy(float)[None], np.array(times))
    q = np.array([p["positions"] for p in points])
    np.testing.assert_allclose(build_leg(ctx.robot.leg).forward(q), s.position[0], atol=1e-9)


def test_a_baseline_as_json_names_what_was_not_checked(evaluated, tmp_path):
    out, _ = _export(evaluated, tmp_path, "poly.json", "json", baseline="polynomial")
    data = json.loads(out.read_text())
    assert data["metadata"]["trajectory"] == "polynomial"
    assert "not checked" in data["metadata"]["constraint_policy"]
    assert len(data["columns"]["q1 [rad]"]) == len(data["columns"]["t [s]"]) > 3


def test_a_row_the_front_lacks_is_refused_and_nothing_written(evaluated, tmp_path):
    work, _, _, evaluate_args = evaluated
    params = evaluate_args[evaluate_args.index("-p") + 1]
    args = cli_args("export", params, optimize=work / "polish" / "optimize", row=10**6)
    result = runner.invoke(app, [*args, "--out", str(tmp_path / "x.csv")])
    assert result.exit_code == 2 and "is not a row of" in result.stderr
    assert not (tmp_path / "x.csv").exists()


def _first_runnable(evaluated, tmp_path, rows):
    """The first of ``rows`` that export takes as a ROS trajectory: the tiny search's front can
    end on a row past a joint's speed, which export refuses by name."""
    refused = []
    for row in rows:
        try:
            return int(row), _export(
                evaluated, tmp_path, f"row{row}.yaml", "ros-yaml", row=int(row)
            )
        except AssertionError as err:
            assert "cannot run it" in str(err), err
            refused.append(row)
    raise AssertionError(f"export refused every front row: {refused}")
