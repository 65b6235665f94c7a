"""A climb's outcome without running one: the check before it, and its records as plain data."""

from __future__ import annotations

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from ftfof.climb import outcome
from ftfof.climb.estimates import SlipEpisode
from ftfof.climb.metrics import SlipTotals
from ftfof.climb.outcome import Climbed
from ftfof.config import LEG_NAMES
from ftfof.errors import ParamsError
from ftfof.identify.estimate import Estimate
from ftfof.trajectory.baselines import BezierTrajectory


def test_a_trajectory_the_rules_refuse_is_refused_unless_allowed(m3f):
    X = np.zeros(12)  # every control point at the start: no lift, no path
    trajectory = BezierTrajectory(m3f.policy, X)
    with pytest.raises(ParamsError, match=r"every leg \(FL, FR, HL, HR\) breaks mst_m3f's rules"):
        outcome.checked_name(m3f, "points", trajectory, X)
    assert (
        outcome.checked_name(m3f, "points", trajectory, X, allow_infeasible=True)
        == "points-infeasible"
    )


def test_a_trajectory_the_robot_can_run_keeps_its_name(m3f):
    from tests.conftest import PUBLISHED_M3F

    X = PUBLISHED_M3F
    assert not m3f.policy.check(X).failed(0)
    assert outcome.checked_name(m3f, "optimum", BezierTrajectory(m3f.policy, X), X) == "optimum"


def _channels(rows: int = 3) -> dict[str, np.ndarray]:
    widths = {"body": 3, "body_rate": 3, "body_acc": 3, "foot": 8, "force": 8, "bonds": 4,
              "curvature": 4, "slip_velocity": 4, "joints": 12, "torque": 12}  # fmt: skip
    c = {k: np.arange(rows * n, dtype=float).reshape(rows, n) for k, n in widths.items()}
    return {**c, "t": np.arange(rows) * 1e-3, "body_plan": np.zeros(rows), "swing": np.ones(rows)}


def test_the_channels_are_named_by_leg_joint_and_axis():
    c = _channels()
    columns = outcome.channel_columns(c)
    assert len(columns) == 3 + 9 + 4 * (7 + 6)
    np.testing.assert_array_equal(columns["body_pitch"], c["body"][:, 2])
    np.testing.assert_array_equal(columns["Fz_FR"], c["force"][:, 3])
    np.testing.assert_array_equal(columns["slip_velocity_HL"], c["slip_velocity"][:, 2])
    np.testing.assert_array_equal(columns["torque_HR2"], c["torque"][:, 10])


def _climbed(fell: bool) -> Climbed:
    spec = SimpleNamespace(climb=SimpleNamespace(controller="both", steps=8))
    run = SimpleNamespace(
        spec=spec,
        fell=fell,
        fall_reason="FL let go" if fell else "",
        error="",
        wall_time=12.34567,
        control={"slipping": 2},
    )
    summary = {"slip_distance": np.float64(2e-3), "slip_path": 6e-3, "max_slip_velocity": 7e-3,
               "steps_done": np.float64(3.0), "jitter": math.nan, "fell": fell,
               "mu_error": np.float64(0.5), "adhesion_error": math.nan,
               "estimated_slips": 1.0}  # fmt: skip
    slip = SlipTotals(np.full(4, 5e-4), np.full(4, 1.5e-3), np.array([7e-3, 1e-3, 0.0, 2e-3]))
    estimate = SlipEpisode(5.0, 3, 0.02, Estimate(0.45, math.inf), Estimate(0.3, 0.25))
    return Climbed("eps_bezier.both", run, {}, [], summary, slip, [estimate])  # type: ignore[arg-type]


def test_a_climbs_document_is_plain_json():
    doc = outcome.document(_climbed(fell=True))
    assert doc["summary"]["jitter"] is None and type(doc["summary"]["steps_done"]) is float
    assert doc["fall"] == "FL let go" and "wall_time_s" not in doc  # the same on any machine
    assert doc["controller"] == "both" and doc["control"] == {"slipping": 2}
    assert list(doc["slip_by_foot"]) == list(LEG_NAMES) and doc["steps"] == []
    (slip,) = doc["slip_estimates"]
    assert slip["foot"] == "HR" and slip["mu"]["error"] == pytest.approx(0.5)
    assert slip["adhesion"] == {"estimate": None, "truth": 0.25, "error": None}
    json.dumps(doc, allow_nan=False)


def test_a_controllers_row():
    row = outcome.controller_row(_climbed(fell=False))
    assert row == {
        "slip_distance": 2e-3,
        "slip_path": 6e-3,
        "max_slip_velocity": 7e-3,
        "mu_error": 0.5,
        "adhesion_error": None,
        "estimated_slips": 1.0,
        "fell": False,
        "fall": "",
        "steps_done": 3.0,
        "control": {"slipping": 2},
    }
    assert type(row["slip_distance"]) is float


def test_a_climb_ends_in_one_line_with_its_outcome_and_time():
    assert outcome.ended(_climbed(fell=True)) == (
        "eps_bezier.both: FELL: FL let go; 3 of 8 steps in 12.3 s"
    )
    assert outcome.ended(_climbed(fell=False)).startswith("eps_bezier.both: ok; 3 of 8 steps")


def test_plain_values():
    assert outcome.plain(np.int64(3)) == 3 and type(outcome.plain(np.int64(3))) is int
    assert outcome.plain(math.inf) is None and outcome.plain(np.float64(math.nan)) is None
    assert outcome.plain("x") == "x"
    assert outcome.CONTROLLERS == ("none", "weights", "replan", "both")
