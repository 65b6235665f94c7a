"""The crawl's plan: strides, the body's advance, the order and the stance strokes."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.climb.gait import LEGS, Gait
from ftfof.climb.simulate import chain_of, gait_of
from ftfof.trajectory.blend import min_jerk
from tests.climb.helpers import spec_of


@pytest.fixture(scope="module")
def gait(params) -> Gait:
    return gait_of(spec_of(params))


def test_min_jerk_runs_from_rest_to_rest():
    s = np.linspace(-0.5, 1.5, 201)
    blend, rate = min_jerk(s)
    assert blend[0] == 0 and blend[-1] == 1 and np.all(np.diff(blend) >= 0)
    assert rate[0] == 0 and rate[-1] == 0 and rate[100] == pytest.approx(1.875)


def test_the_body_advances_a_quarter_stride_per_step_and_rests_in_the_swings(gait, params):
    stride = params.selected_robot.landing.x
    assert gait.advance == pytest.approx(stride / LEGS)
    ends = np.array([gait.lift_off(k) for k in range(gait.steps)])
    x, v = gait.body(ends)
    assert x == pytest.approx(gait.advance * np.arange(gait.steps))
    assert np.all(v == 0)
    swings = ends[:, None] + np.linspace(0, gait.swing + gait.hold, 7)[None]
    _, vs = gait.body(swings.ravel())
    assert np.all(vs == 0)
    assert gait.body(np.array([gait.end + 1.0]))[0][0] == pytest.approx(gait.steps * gait.advance)


def test_the_body_plan_is_smooth(gait):
    t = np.linspace(0, gait.end, 20001)
    x, v = gait.body(t)
    assert np.max(np.abs(np.gradient(x, t) - v)) < 0.01 * np.max(v)


def test_each_foot_moves_one_stride_per_cycle_and_returns_to_its_stroke(gait):
    start, _ = gait.feet(0.0)
    after, _ = gait.feet(gait.lift_off(LEGS))  # one cycle: every leg swung once
    assert after[:, 0] - start[:, 0] == pytest.approx(np.full(LEGS, LEGS * gait.advance))
    body, _ = gait.body(np.array([gait.lift_off(LEGS)]))
    rel_before = start[:, 0] - gait.hips
    rel_after = after[:, 0] - body[0] - gait.hips
    assert rel_after == pytest.approx(rel_before)


def test_only_the_swinging_leg_moves(gait):
    for k in range(LEGS):
        t0 = gait.lift_off(k)
        before, _ = gait.feet(t0)
        mid, vel = gait.feet(t0 + gait.swing / 2)
        moved = np.flatnonzero(np.any(mid != before, axis=1))
        assert moved.tolist() == [gait.leg_of(k)]
        assert np.any(vel[gait.leg_of(k)] != 0)


def test_the_first_to_swing_starts_at_p0_of_its_leg(gait, params):
    chain = chain_of(params.selected_robot)
    feet = gait.initial_feet()
    first = gait.order[0]
    assert feet[first] - gait.hips[first] == pytest.approx(-chain.hip[0])


def test_the_gait_order_must_name_each_leg_once(params_dict):
    from pydantic import ValidationError

    from ftfof.config import Params

    params_dict["robots"]["mst_m3f"]["climber"]["gait"] = [0, 0, 1, 2]
    with pytest.raises(ValidationError, match="each leg 0-3"):
        Params.model_validate(params_dict)
