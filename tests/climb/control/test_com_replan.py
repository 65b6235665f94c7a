"""The one-step CoM planner as the replan controllers' re-planner, on the polynomial baseline's
crawl of MST-M3F: FL's swing (the crawl's second step), a hind pad found weak."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.climb.control.com_replan import PlannerReplanner
from ftfof.climb.control.replan import ReplanRequest
from ftfof.climb.gait import Gait
from ftfof.climb.simulate import chain_of, gait_of
from ftfof.demand import robot_mass
from tests.climb.helpers import spec_of

STEP = 1  # FL's
HR = 3


@pytest.fixture(scope="module")
def gait(params) -> Gait:
    return gait_of(spec_of(params))


@pytest.fixture
def replanner(params, gait) -> PlannerReplanner:
    robot = params.selected_robot
    return PlannerReplanner(gait, robot_mass(robot), float(chain_of(robot).hip[1]))


def request(gait: Gait, into: float, adhesion: float, rate: float = -3e-3) -> ReplanRequest:
    """HR slips ``into`` s after FL's lift-off, its pad believed to hold ``adhesion`` N (its
    pull-off 0.4 of that), the others mu 0.6, F_adh 20 N, pull-off 8 N; the body 1 mm off its
    plan and sliding down at ``rate``."""
    now = gait.lift_off(STEP) + into
    leg = gait.leg_of(STEP)
    stance = np.ones(4, bool)
    stance[leg] = False
    friction, pads, pull = np.full(4, 0.6), np.full(4, 20.0), np.full(4, 8.0)
    pads[HR], pull[HR] = adhesion, 0.4 * adhesion
    x = gait.body(np.array([now]))[0][0] - 1e-3
    return ReplanRequest(
        now,
        HR,
        friction,
        pads,
        stance,
        gait.feet(now)[0][:, 0],
        np.array([x, 1e-3, 0.0]),
        np.array([rate, 0.0, 0.0]),
        gait.body,
        pull,
    )


def step_end(gait: Gait) -> float:
    return gait.lift_off(STEP) + gait.swing + gait.hold + gait.shift


@pytest.mark.parametrize("into", [0.0, 0.4, 1.1])  # in FL's swing, and in its landing hold
def test_a_weak_hind_pad_is_replanned_from_the_plans_state_to_the_goal_at_rest(
    gait, replanner, into
):
    req = request(gait, into, adhesion=2.0)
    plan = replanner(req)
    assert plan is not None and replanner.counts.planned == 1
    x, v = plan(np.array([req.time]))
    was, was_rate = gait.body(np.array([req.time]))  # not the body's state: it follows the slide
    assert x[0] == pytest.approx(was[0], abs=1e-12) and v[0] == pytest.approx(
        was_rate[0], abs=1e-12
    )
    end = step_end(gait)
    t = np.linspace(req.time, end, 2001)
    x, v = plan(t)
    assert np.all(np.isfinite(x)) and np.abs(np.diff(x)).max() < 1e-4  # no jump on the way
    goal, _ = gait.body(np.array([end]))
    assert x[-1] == pytest.approx(goal[0], abs=1e-12) and v[-1] == pytest.approx(0, abs=1e-12)
    later = np.array([end + 0.3, gait.end])
    assert np.array_equal(np.stack(plan(later)), np.stack(gait.body(later)))
    before = np.array([req.time - 0.1])
    assert np.array_equal(np.stack(plan(before)), np.stack(gait.body(before)))


def test_the_replan_differs_from_the_gait_plan_only_between_now_and_the_step_end(gait, replanner):
    req = request(gait, 0.4, adhesion=2.0)
    plan = replanner(req)
    assert plan is not None
    t = np.linspace(req.time, step_end(gait), 101)[1:-1]
    assert np.abs(plan(t)[0] - gait.body(t)[0]).max() > 1e-4


def test_a_pad_too_weak_for_any_com_keeps_the_plan(gait, replanner):
    assert replanner(request(gait, 0.4, adhesion=0.2)) is None
    assert replanner.counts.infeasible == 1 and replanner.counts.planned == 0


def test_a_slip_in_the_body_advance_or_with_a_second_foot_off_keeps_the_plan(gait, replanner):
    advance = request(gait, gait.swing + gait.hold + 0.1, adhesion=2.0)
    assert replanner(advance) is None
    off = request(gait, 0.4, adhesion=2.0)
    off.stance[2] = False
    assert replanner(off) is None
    assert replanner.counts.outside == 2 and replanner.counts.planned == 0
