"""The one-step CoM planner on our robot: HL's step of the crawl, from params.yaml's MST-M3F
(0.81 kg, hips 0.20 m apart and 0.04 m off the wall), pads of mu 0.45-0.8 and F_adh 2-20 N."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from ftfof.climb.control.com_step import Foothold, Step
from ftfof.climb.control.cones import PHASES, InfeasibleStepError
from ftfof.climb.control.planner import (
    ComPlan,
    accel_ratio,
    feasible_interval,
    plan_step,
    replan_swing,
)
from ftfof.climb.simulate import chain_of
from ftfof.config import GRAVITY
from ftfof.demand import robot_mass

SAMPLES = 200
TOL = 1e-6  # N: the planner's checks hold to 1e-9 N at their bounds
HL, HR, FL = 2, 3, 0


@pytest.fixture(scope="module")
def step_of(params):
    """A builder of HL's step (the crawl's first: HL, FL, HR, FR) with each foot's mu and F_adh:
    the feet where the gait has them, the CoM at the hips' height advancing a quarter stride
    over the pre-swing (the gait's shift time), swing (T3) and post-swing."""
    robot = params.selected_robot
    climber = robot.climber
    hip = chain_of(robot).hip  # the hip relative to its foot's start on the wall
    half = climber.hip_spacing / 2
    hips = np.array([half, half, -half, -half])
    advance = robot.landing.x / 4
    feet_x = hips - hip[0] + advance * np.argsort(climber.gait)
    start = np.array([0.0, hip[1]])
    durations = (params.climb.shift_time, robot.timing.T3, params.climb.shift_time)

    def build(mu=(0.6,) * 4, adhesion=(20.0,) * 4) -> Step:
        feet = tuple(
            Foothold(np.array([x, 0.0]), m, f) for x, m, f in zip(feet_x, mu, adhesion, strict=True)
        )
        landing = dataclasses.replace(feet[HL], position=np.array([feet_x[HL] + 4 * advance, 0]))
        goal = start + np.array([advance, 0.0])
        return Step(robot_mass(robot), start, goal, feet, HL, landing, durations)

    return build


@pytest.fixture(scope="module")
def weak_hind(step_of) -> Step:
    """HR's pad holds 2 N only: alone behind in HL's swing, it slides unless the CoM slows."""
    return step_of(adhesion=(20.0, 20.0, 20.0, 2.0))


def cone_values(plan: ComPlan, t: np.ndarray, step: Step | None = None) -> np.ndarray:
    """(N, feet, 3) f_n + F_adh, mu (f_n + F_adh) - f_t, mu (f_n + F_adh) + f_t of every foot
    holding at ``t``, the pads' values from ``step`` (default the plan's); nan for a lifted one."""
    step = step or plan.step
    f = plan.forces(t)
    T1, T2, _ = step.durations
    phase = np.searchsorted([T1, T1 + T2], t, side="right")
    out = np.full((*f.shape[:2], 3), np.nan)
    for p in range(len(PHASES)):
        feet, holds = step.stance(p)
        mu = np.array([h.mu for h in feet])
        adhesion = np.array([h.adhesion for h in feet])
        at = phase == p
        c = f[at][..., 1] + adhesion
        values = np.stack([c, mu * c - f[at][..., 0], mu * c + f[at][..., 0]], axis=-1)
        values[:, ~holds] = np.nan
        out[at] = values
    return out


def times(plan: ComPlan) -> np.ndarray:
    return np.linspace(plan.starts[0], plan.end, SAMPLES)


def test_the_plan_keeps_every_holding_pad_in_its_cone(weak_hind):
    plan = plan_step(weak_hind)
    assert plan.x == plan.interval.lower > 0  # rest in the swing would let HR slide
    limit = plan.interval.lower_limit
    assert (limit.foot, limit.phase) == ("HR", "swing")
    values = cone_values(plan, times(plan))
    assert np.nanmin(values) >= -TOL


def test_the_forces_carry_the_planned_com(weak_hind):
    """sum f = m (p'' - g) and sum (p_i - p) x f_i = 0, each foot where the phase has it."""
    plan = plan_step(weak_hind)
    t = times(plan)
    p, _, a = plan.state(t)
    f = plan.forces(t)
    m = weak_hind.mass
    assert f.sum(axis=1) == pytest.approx(m * (a - [-GRAVITY, 0.0]), abs=1e-9)
    T1, T2, _ = weak_hind.durations
    post = t >= T1 + T2
    feet = np.array([h.position for h in weak_hind.feet])
    where = np.broadcast_to(feet, f.shape).copy()
    where[post, HL] = weak_hind.landing.position
    arm = where - p[:, None]
    moment = arm[..., 0] * f[..., 1] - arm[..., 1] * f[..., 0]
    assert moment.sum(axis=1) == pytest.approx(0.0, abs=1e-9)


def test_the_com_runs_from_rest_to_the_goal_at_rest_in_c1_pieces(weak_hind):
    plan = plan_step(weak_hind)
    p, v, _ = plan.state(np.array([0.0, plan.end]))
    assert p[0] == pytest.approx(weak_hind.start) and p[1] == pytest.approx(weak_hind.goal)
    assert v == pytest.approx(np.zeros((2, 2)), abs=1e-12)
    joints = plan.starts[1:]
    before = plan.state(joints - 1e-9)
    after = plan.state(joints + 1e-9)
    for x, y in zip(before[:2], after[:2], strict=True):
        assert x == pytest.approx(y, abs=1e-8)
    assert np.abs(before[2] - after[2]).max() > 0.1  # C1, not C2: the paper's pieces
    across = (p - weak_hind.goal) @ [-plan.direction[1], plan.direction[0]]
    assert np.abs(across).max() < 1e-12  # on the line through the goal


def test_the_swing_strays_from_the_goal_no_further_than_at_lift_off(weak_hind):
    """gamma's choice: the swing starts behind the goal, passes it, and turns as far beyond it
    as it started behind."""
    plan = plan_step(weak_hind)
    T1, T2, T3 = weak_hind.durations
    assert accel_ratio(T2, T3) < -T3 / T2  # the turning point lies inside the swing
    p, _, _ = plan.state(np.linspace(T1, T1 + T2, 2001))
    s = (p - weak_hind.goal) @ plan.direction
    assert s[0] < 0 and s.max() == pytest.approx(-s[0], rel=1e-6)


def first_failure(step_of) -> tuple[float, InfeasibleStepError]:
    """HR's F_adh lowered in 0.25 N steps from 20 N: the first it cannot step with."""
    for adhesion in np.arange(20.0, -0.1, -0.25):
        try:
            plan_step(step_of(adhesion=(20.0, 20.0, 20.0, adhesion)))
        except InfeasibleStepError as error:
            return adhesion, error
    raise AssertionError("HR held without any adhesion")


def test_a_hind_pad_losing_adhesion_stops_the_step_naming_it(step_of):
    adhesion, error = first_failure(step_of)
    conflict = error.interval
    assert conflict.empty and 0 < adhesion < 20
    assert ("HR", "swing", "slides down the wall") in [
        (limit.foot, limit.phase, limit.side)
        for limit in (conflict.lower_limit, conflict.upper_limit)
    ]
    assert "HR slides down the wall in swing" in str(error)


def test_a_slippery_pad_sheds_its_shear(step_of):
    """W_f = diag(1 / mu^2, 1): each foot's tangential share goes as its mu^2, so FL on a
    slippery spot holds a ninth of the others' shear and the step stays feasible."""
    plan = plan_step(step_of(mu=(0.2, 0.6, 0.6, 0.6)))
    f = plan.forces(np.array([0.0]))[0]
    assert f[FL, 0] == pytest.approx(f[HR, 0] / 9)


def test_a_replan_mid_swing_after_a_pad_proves_slippery_keeps_the_cones(weak_hind):
    """0.4 s into HL's swing FL turns out to hold at mu 0.5: the shear it sheds falls on the
    weak HR, and the plan's own swing (alpha = gamma beta) would let HR slide; the re-plan from
    the CoM's state holds every pad over the rest of the step."""
    plan = plan_step(weak_hind)
    T1, T2, T3 = weak_hind.durations
    elapsed = 0.4
    now = T1 + elapsed
    p, v, _ = plan.state(np.array([now]))
    feet = list(weak_hind.feet)
    feet[FL] = dataclasses.replace(feet[FL], mu=0.5)
    slippery = dataclasses.replace(weak_hind, feet=tuple(feet))
    replan = replan_swing(slippery, plan.direction, elapsed, p[0], v[0])
    old = accel_ratio(T2, T3) * plan.x
    assert not replan.interval.lower <= old <= replan.interval.upper
    t = times(replan)
    assert t[0] == now
    assert np.nanmin(cone_values(replan, t)) >= -TOL
    start, end = replan.state(np.array([now, replan.end]))[:2], replan.state(np.array([plan.end]))
    assert start[0][0] == pytest.approx(p[0]) and start[1][0] == pytest.approx(v[0])
    assert end[0][0] == pytest.approx(weak_hind.goal) and end[1][0] == pytest.approx([0, 0])


def test_the_feasible_interval_shrinks_as_a_pad_loses_adhesion(step_of):
    widths = [
        feasible_interval(step_of(adhesion=(20.0, 20.0, 20.0, f))).width
        for f in (20.0, 10.0, 5.0, 2.0, 1.0, 0.0)
    ]
    assert np.all(np.diff(widths) < 0)
    assert widths[0] > 0 > widths[-1]


def test_a_replan_needs_a_time_within_the_swing(weak_hind):
    with pytest.raises(ValueError, match="within the swing"):
        replan_swing(
            weak_hind, np.array([1.0, 0.0]), weak_hind.durations[1], np.zeros(2), np.zeros(2)
        )


def test_random_pads_planned_and_replanned_hold_wherever_sampled(step_of):
    """Proposition 1 and the Bezier checks are sufficient: any plan or re-plan that comes back
    holds every pad at every sample (pads of mu 0.45-0.8 and F_adh 1-20 N, re-planned at a
    random time in the swing with every mu 10 % lower)."""
    rng = np.random.default_rng(7)
    planned = replanned = 0
    for _ in range(60):
        step = step_of(mu=rng.uniform(0.45, 0.8, 4), adhesion=rng.uniform(1.0, 20.0, 4))
        try:
            plan = plan_step(step)
        except InfeasibleStepError:
            continue
        planned += 1
        assert np.nanmin(cone_values(plan, times(plan))) >= -TOL
        elapsed = rng.uniform(0, step.durations[1])
        p, v, _ = plan.state(np.array([step.durations[0] + elapsed]))
        feet = tuple(dataclasses.replace(f, mu=0.9 * f.mu) for f in step.feet)
        try:
            replan = replan_swing(
                dataclasses.replace(step, feet=feet), plan.direction, elapsed, p[0], v[0]
            )
        except InfeasibleStepError:
            continue
        replanned += 1
        assert np.nanmin(cone_values(replan, times(replan))) >= -TOL
    assert planned > 40 and replanned > 30


def test_a_pull_off_below_f_adh_bounds_the_pulls_and_leaves_the_cones_as_they_were(step_of):
    """Foothold.pull_off: the pad's pull bound, f_n >= -pull-off, apart from the cone's shift
    F_adh (the controller's pads: pull-off 10.4 N against F_adh 34.7 N on acrylic). HL's step
    pulls on FR most (1.1 N, the trunk's moment): a pull-off a little above that narrows the
    betas, one at half of it leaves none (the post-swing's rest pulls as much)."""
    base = step_of()
    f = plan_step(base).forces(times(plan_step(base)))
    pull = -float(np.nanmin(f[..., 1]))
    FR = 1
    assert pull > 0.5 and -float(np.nanmin(f[:, FR, 1])) == pull

    def with_pull_off(limit: float) -> Step:
        feet = list(base.feet)
        feet[FR] = dataclasses.replace(feet[FR], pull_off=limit)
        return dataclasses.replace(base, feet=tuple(feet))

    tight = with_pull_off(1.2 * pull)
    assert 0 < feasible_interval(tight).width < feasible_interval(base).width
    plan = plan_step(tight)
    g = plan.forces(times(plan))
    assert np.nanmin(g[:, FR, 1]) >= -1.2 * pull - TOL
    assert np.nanmin(cone_values(plan, times(plan))) >= -TOL
    with pytest.raises(InfeasibleStepError, match="FR pulls off the wall"):
        plan_step(with_pull_off(pull / 2))
    assert with_pull_off(base.feet[FR].adhesion).feet[FR].pull == base.feet[FR].pull
