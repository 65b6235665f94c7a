"""The contact-force QP on the M3F climber's legs: tracking, the pyramids, the torque limits,
warm starts and failures."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ftfof.climb.control.forces import (
    ForceDistributor,
    Stance,
    Status,
    constraints,
    wrench_map,
)
from tests.climb.control.stances import GRAVITY, MASS, STROKE, stance_of, static_wrench

TOL = 1e-7  # N, N m: what the solver's 1e-9 leaves of a constraint


def assert_inside(stance: Stance, forces: np.ndarray) -> None:
    """Every pyramid and torque limit holds."""
    ft, fn = forces[:, 0], forces[:, 1]
    assert np.all(np.abs(ft) <= stance.friction * (fn + stance.adhesion) + TOL)
    assert np.all(fn >= -stance.pull_off - TOL)
    torques = np.einsum("nij,ni->nj", stance.jacobian, forces)
    assert np.all(np.abs(torques) <= stance.torque_limit + TOL)


def test_the_wrench_map_takes_moments_about_the_com_in_the_pitch_sense():
    A = wrench_map(np.array([[0.1, -0.04]]))
    pressing_ahead, pushed_up_below = A @ [0.0, 1.0], A @ [1.0, 0.0]
    assert pressing_ahead == pytest.approx([0.0, 1.0, 0.1])  # of the CoM
    assert pushed_up_below == pytest.approx([1.0, 0.0, 0.04])


def test_a_feasible_wrench_is_tracked_inside_every_cone(m3f):
    stance = stance_of(m3f)
    limits = stance.torque_limit.copy()
    limits[:, 2] = np.inf  # a virtual third joint (the spatial leg's) has no limit
    accelerating = np.array([MASS * (GRAVITY + 0.5), 0.3, 0.02])
    cases = [(stance, static_wrench()), (replace(stance, torque_limit=limits), accelerating)]
    for stance, wrench in cases:
        out = ForceDistributor().solve(stance, wrench)
        assert out.status is Status.SOLVED
        assert np.abs(out.residual).max() < 1e-4 * wrench[0]
        assert_inside(stance, out.forces)
        expected = -np.einsum("nij,ni->nj", stance.jacobian, out.forces)
        assert out.torques == pytest.approx(expected)
    # the moment of the weight (the CoM off the wall) is held by pulling fore and pressing hind
    assert out.forces[:2, 1].max() < 0 < out.forces[2:, 1].min()


def test_a_pad_that_holds_little_pull_hands_its_pull_to_the_other_fore_foot(m3f):
    """The pull-off cuts FL's pyramid below its apex: FL pulls at most 0.2 N, FR takes the rest
    of the fore feet's pull, and the wrench is still met."""
    stance = stance_of(m3f)
    free = ForceDistributor().solve(stance, static_wrench())
    assert free.forces[0, 1] < -0.5
    pull_off = np.full(4, stance.adhesion[0])
    pull_off[0] = 0.2
    weak = replace(stance, pull_off=pull_off)
    out = ForceDistributor().solve(weak, static_wrench())
    assert out.solved and out.forces[0, 1] == pytest.approx(-0.2, abs=1e-6)
    assert out.forces[1, 1] < free.forces[1, 1] - 0.1
    assert np.abs(out.residual).max() < 1e-4 * static_wrench()[0]
    assert_inside(weak, out.forces)


def test_a_poor_pad_hands_its_load_to_the_others(m3f):
    stance = stance_of(m3f)
    nominal = ForceDistributor().solve(stance, static_wrench())
    friction, adhesion = stance.friction.copy(), stance.adhesion.copy()
    friction[1], adhesion[1] = 0.1, 0.5  # FR's pad barely holds
    poor = replace(stance, friction=friction, adhesion=adhesion)
    out = ForceDistributor().solve(poor, static_wrench())
    assert out.status is Status.SOLVED
    assert np.abs(out.residual).max() < 1e-4 * MASS * GRAVITY
    assert_inside(poor, out.forces)
    assert abs(out.forces[1, 0]) < 0.2 * abs(nominal.forces[1, 0])
    others = [0, 2, 3]
    assert np.abs(out.forces[others, 0]).sum() > np.abs(nominal.forces[others, 0]).sum() + 1.0


def test_tight_torque_limits_are_met_and_active(m3f):
    stance = stance_of(m3f)
    free = ForceDistributor().solve(stance, static_wrench())
    leg, joint = 3, int(np.argmax(np.abs(free.torques[3])))
    limits = stance.torque_limit.copy()
    limits[leg, joint] = 0.5 * abs(free.torques[leg, joint])
    tight = replace(stance, torque_limit=limits)
    out = ForceDistributor().solve(tight, static_wrench())
    assert out.status is Status.SOLVED
    assert_inside(tight, out.forces)
    assert abs(out.torques[leg, joint]) == pytest.approx(limits[leg, joint], abs=1e-6)
    assert np.abs(out.residual).max() < 1e-4 * MASS * GRAVITY  # the other legs make it up


def test_a_warm_start_returns_the_cold_solution(m3f):
    warm, cold = ForceDistributor(), ForceDistributor()
    for k in range(20):
        stance = stance_of(m3f, STROKE + 0.002 * k)
        wrench = static_wrench() + np.array([0.1, 0.05, 0.01]) * np.sin(0.3 * k)
        a = warm.solve(stance, wrench)
        cold.reset()
        b = cold.solve(stance, wrench)
        assert a.status is b.status is Status.SOLVED
        assert a.forces == pytest.approx(b.forces, abs=1e-6)


def test_a_change_of_stance_builds_the_solver_anew(m3f):
    solver = ForceDistributor()
    solver.solve(stance_of(m3f), static_wrench())
    three = stance_of(m3f, STROKE[:3])  # HR in the air
    out = solver.solve(three, static_wrench())
    assert out.status is Status.SOLVED and out.forces.shape == (3, 2)
    assert out.forces == pytest.approx(ForceDistributor().solve(three, static_wrench()).forces)


def test_an_infeasible_stance_is_a_status_not_an_exception(m3f):
    """Pads that must be pressed to hold (F_adh < 0) on servos that give no torque: no force
    satisfies both; the answer says so with NaN forces, and the next step solves afresh."""
    stance = stance_of(m3f)
    stuck = replace(stance, adhesion=np.full(4, -1.0), torque_limit=np.zeros((4, 3)))
    solver = ForceDistributor()
    out = solver.solve(stuck, static_wrench())
    assert out.status is Status.INFEASIBLE and not out.solved
    assert np.isnan(out.forces).all() and np.isnan(out.torques).all()
    assert solver.solve(stance, static_wrench()).solved


def test_bad_numbers_are_refused_before_the_solver(m3f):
    stance = stance_of(m3f)
    jacobian = stance.jacobian.copy()
    jacobian[0, 0, 0] = np.nan
    with pytest.raises(ValueError, match="jacobian is not finite"):
        replace(stance, jacobian=jacobian)
    with pytest.raises(ValueError, match="friction has shape"):
        replace(stance, friction=np.ones(3))
    with pytest.raises(ValueError, match="wrench"):
        ForceDistributor().solve(stance, np.array([1.0, 0.0]))


def test_the_constraints_hold_the_pyramid_and_ignore_the_slack(m3f):
    stance = stance_of(m3f)
    C, lower, upper = constraints(stance)
    assert C.shape == (6 * 4, 2 * 4 + 3) and not C[:, -3:].any()
    assert np.isinf(lower[:12]).all() and upper[:3] == pytest.approx([4.8, 4.8, 8.0])
