"""Controller export: the foot path sampled at a rate, with joint angles the leg reaches."""

import json
from dataclasses import replace

import numpy as np
import pytest
import yaml
from scipy.stats import qmc

from ftfof.evaluate.export import (
    COLUMNS,
    EXPORT_MAX_RATE_HZ,
    EXPORT_MAX_SAMPLES,
    ExportRateError,
    controller_trajectory,
    limit_breaches,
    render,
    sample_count,
)
from ftfof.kinematics.legs import build_leg
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.sampling import sample_feasible


def _export(ctx, X, rate_hz):
    """``X`` of ``ctx``'s robot for its controller."""
    trajectory, leg = BezierTrajectory(ctx.policy, X), build_leg(ctx.robot.leg)
    return controller_trajectory(trajectory, ctx.policy.timing.T3, leg, rate_hz)


@pytest.mark.parametrize("ctx_name", ["m3f", "mst_q"])
def test_joint_angles_reproduce_the_foot_path(ctx_name, request):
    ctx = request.getfixturevalue(ctx_name)
    policy, leg = ctx.policy, build_leg(ctx.robot.leg)
    X = sample_feasible(policy, 1, seed=4).X[0]
    out = _export(ctx, X, 250.0)
    T3 = policy.timing.T3
    assert out.table.shape == (int(np.floor(T3 * 250 + 1e-9)) + 1, len(COLUMNS))
    t = out.table[:, 0]
    np.testing.assert_allclose(np.diff(t), 1 / 250, rtol=1e-9)
    s = policy.sample(X[None], t)
    np.testing.assert_allclose(out.table[:, 1:3], s.position[0], atol=1e-12)
    np.testing.assert_allclose(out.table[:, 3:5], s.velocity[0], atol=1e-12)
    theta = out.table[:, 5:8]
    np.testing.assert_allclose(leg.forward(theta), s.position[0], atol=1e-9)  # IK round trip
    if ctx_name == "m3f":  # its Ppl box lies inside the planar leg's joint ranges
        assert out.within_joint_limits
    # joint rates agree with J(theta) dq = v in the foot plane
    J = leg.jacobian(theta)
    v = np.einsum("nij,nj->ni", J, out.table[:, 8:11])
    np.testing.assert_allclose(v, s.velocity[0], atol=1e-9)


def test_unreachable_point_is_named(m3f):
    X = sample_feasible(m3f.policy, 1, seed=4).X[0].copy()
    X[6:9] = 5.0  # P3z..P5z five metres from the wall
    with pytest.raises(ValueError, match="cannot reach") as raised:
        _export(m3f, X, 100.0)
    assert not isinstance(raised.value, ExportRateError)  # not the rate's fault


def test_a_rate_too_low_for_three_samples_is_the_rates_fault(m3f):
    X = sample_feasible(m3f.policy, 1, seed=4).X[0]
    with pytest.raises(ExportRateError, match="fewer than 3 samples"):
        _export(m3f, X, 0.5)


def test_a_rate_or_a_sample_count_beyond_its_bound_is_refused_before_sampling():
    assert sample_count(1.0, EXPORT_MAX_RATE_HZ) == EXPORT_MAX_RATE_HZ + 1  # the bound holds
    with pytest.raises(ExportRateError, match=r"1e\+09 Hz is beyond the bound of 100000 Hz"):
        sample_count(1.0, 1e9)
    with pytest.raises(ExportRateError, match="nan Hz is beyond"):
        sample_count(1.0, float("nan"))
    with pytest.raises(ExportRateError, match=f"beyond the bound of {EXPORT_MAX_SAMPLES} samples"):
        sample_count(20.0, EXPORT_MAX_RATE_HZ)  # a long step at the highest rate


def test_a_joint_out_of_range_or_too_fast_is_named_with_its_time(m3f):
    X = sample_feasible(m3f.policy, 1, seed=4).X[0]
    out = _export(m3f, X, 100.0)
    leg = build_leg(m3f.robot.leg)
    before = limit_breaches(out, leg)
    assert not any(b.startswith(("q2 =", "dq3 =")) for b in before)
    table = out.table.copy()
    table[7, 6] = leg.joint_limits[1, 1] + 0.1  # q2 past its upper bound at the eighth sample
    table[3:, 10] = 2 * leg.speed_limits[2]  # dq3 twice its limit from the fourth
    after = limit_breaches(replace(out, table=table), leg)
    q2 = next(b for b in after if b.startswith("q2 ="))
    dq3 = next(b for b in after if b.startswith("dq3 ="))
    assert q2.startswith(f"q2 = {table[7, 6]:.4f} rad at t = {table[7, 0]:.4f} s, outside")
    assert f"at t = {table[3, 0]:.4f} s, beyond the {leg.speed_limits[2]:g} rad/s limit" in dq3


def test_each_format_renders_the_table_and_its_metadata(m3f):
    X = sample_feasible(m3f.policy, 1, seed=4).X[0]
    out = _export(m3f, X, 50.0)
    meta = {"robot": "mst_m3f", "frame_id": "foot", "units": {"q": "rad"}}
    csv = render(out, meta, "csv")
    assert csv.startswith("# robot: mst_m3f\n# frame_id: foot\n# units.q: rad\n")
    body = [line for line in csv.splitlines() if not line.startswith("#")]
    np.testing.assert_allclose(np.loadtxt(body[1:], delimiter=","), out.table, rtol=1e-8)
    ros = yaml.safe_load(render(out, meta, "ros-yaml"))
    assert len(ros["points"]) == len(out.table) and ros["header"]["frame_id"] == "foot"
    assert ros["points"][-1]["time_from_start"] == {"sec": 1, "nanosec": 0}
    assert json.loads(render(out, meta, "json"))["metadata"] == meta
    with pytest.raises(ValueError, match="unknown format"):
        render(out, meta, "xml")


def outrunning_a_joint(policy):
    """A Sobol draw every rule but the leg's joint limits accepts (about one in eight feasible
    draws of MST-M3F's box and speed limits outruns its knee or ankle)."""
    joints = "the leg's joints within range and speed"
    X, _ = policy.shaped(qmc.Sobol(policy.n_free, seed=0).random(4096))
    report = policy.check(X)
    others = np.delete(report.violations, report.names.index(joints), axis=1)
    fails = (report.violations[:, report.names.index(joints)] > 0) & ~np.any(others > 0, axis=1)
    assert fails.any()
    return X[np.flatnonzero(fails)[0]]


def test_a_run_the_robot_cannot_make_is_refused_naming_the_rule(m3f):
    from ftfof.errors import ParamsError
    from ftfof.evaluate.export import runnable

    X = sample_feasible(m3f.policy, 1, seed=0).X[0]
    out = runnable(m3f, "row0", BezierTrajectory(m3f.policy, X), X, 100.0)
    assert out.table.shape[1] == len(COLUMNS)
    with pytest.raises(ParamsError, match="--rate"):
        runnable(m3f, "row0", BezierTrajectory(m3f.policy, X), None, 0.5)
    fast = outrunning_a_joint(m3f.policy)  # the foot's box and speed allow it, the leg does not
    with pytest.raises(ParamsError, match="cannot run it: joint_limit: the leg's joints"):
        runnable(m3f, "fast", BezierTrajectory(m3f.policy, fast), fast, 100.0)
    trajectory = BezierTrajectory(m3f.policy, fast)  # as a path without its row: the leg's check
    with pytest.raises(ParamsError, match="leg cannot run it: dq"):
        runnable(m3f, "fast", trajectory, None, 100.0)
    far = X.copy()
    far[6:9] = 5.0
    with pytest.raises(ParamsError, match=f"{m3f.name} cannot run it"):
        runnable(m3f, "far", BezierTrajectory(m3f.policy, far), far, 100.0)


def test_the_metadata_names_the_robot_frame_source_and_control_points(m3f):
    from ftfof.evaluate.export import export_metadata

    X = np.arange(12) * 1e-3
    meta = export_metadata(m3f, "glass", "row4", 100.0, "abc", {"front_row": 4}, "none", X)
    assert list(meta)[:3] == ["ftfof", "robot", "leg"]
    assert (meta["robot"], meta["front_row"], meta["simulated"]) == (m3f.name, 4, "none")
    assert meta["control_points_mm"]["P3x"] == 0.0
    assert "control_points_mm" not in export_metadata(m3f, "g", "poly", 1.0, "a", {}, "n", None)


def test_the_simulated_figures_are_found_by_row_or_by_name():
    from ftfof.evaluate.export import simulated_figures

    summary = {
        "optimum_front_row": 7,
        "table": {"optimum": {"peak_pull": 6.0, "peak_pull_change": -3.0}, "polynomial": {}},
        "front_simulated": {"members": [{"row": 9, "peak_pull": 5.0, "other": 1.0}]},
    }
    assert simulated_figures(summary, "optimum", 7) == {"peak_pull": 6.0}
    assert simulated_figures(summary, "row9", 9) == {"peak_pull": 5.0}
    assert simulated_figures(summary, "polynomial", None) == {}
    assert simulated_figures(summary, "row3", 3) == "not simulated by evaluate"
