"""The control step alone: it runs the controller at its rate and hands it the trunk, the
joints, the feet on the wall, the stance pads' slide and the force window."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.climb.control.feedforward import CONTROL_RATE_HZ
from ftfof.climb.control_step import ControlStep
from ftfof.climb.sensing import SlipMeter
from tests.climb.test_recorder import HANDLES, N


class Recording:
    """A controller (:class:`ftfof.climb.control_step.Controller`) that keeps what it was
    handed and answers with fixed torques."""

    def __init__(self):
        self.anchored = np.array([False, True, False, False])
        self.calls: list[tuple] = []

    def step(self, *args):
        self.calls.append(args)
        return np.full((4, 3), 0.5), None


def _forces(leg: int):
    return None


def test_the_controller_runs_once_a_period_on_the_robots_state():
    control = Recording()
    step = ControlStep(control, HANDLES, SlipMeter(HANDLES), _forces)
    q, qd = np.arange(N, dtype=float), -np.arange(N, dtype=float)
    stance = np.array([True, True, True, False])
    period = 1.0 / CONTROL_RATE_HZ
    assert step.due(0.0) and step.anchored is control.anchored
    torques, plan = step.step(0.0, q, qd, "the plan", stance)
    np.testing.assert_array_equal(torques, 0.5)
    assert plan is None and not step.due(0.5 * period) and step.due(period)
    t, body, rate, handed_plan, theta, feet, handed_stance, slip, forces = control.calls[0]
    assert t == 0.0 and handed_plan == "the plan" and forces is _forces
    np.testing.assert_array_equal(body, q[:3])
    np.testing.assert_array_equal(rate, qd[:3])
    body[0] = 99.0  # a copy: the controller cannot move the solver's state
    assert q[0] == 0.0
    np.testing.assert_array_equal(theta, q[3:15].reshape(4, 3))
    np.testing.assert_array_equal(feet, HANDLES.foot_ref[:, 0] + q[[15, 17, 19, 21]])
    np.testing.assert_array_equal(handed_stance, stance)
    np.testing.assert_array_equal(slip, 0.0)


def test_a_controller_that_re_plans_hands_back_its_plan():
    control = Recording()
    control.step = lambda *args: (np.zeros((4, 3)), "a new plan")
    step = ControlStep(control, HANDLES, SlipMeter(HANDLES), _forces)
    assert step.step(0.0, np.zeros(N), np.zeros(N), "the plan", np.ones(4, bool))[1] == "a new plan"
    assert step.next_control == pytest.approx(1.0 / CONTROL_RATE_HZ)
