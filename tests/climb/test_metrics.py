"""A step's servo torques read against the robot's limits."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.climb.metrics import _torque


def test_torques_within_their_limits_pass_with_their_largest_share():
    limits = np.array([1.5, 1.5, np.inf])
    torque = np.zeros((5, 12))
    torque[2, 4] = -0.75  # FR's knee, half its limit
    torque[3, 2] = 5.0  # a virtual joint has no limit
    out = _torque(torque, limits)
    assert out == {"torque_ratio": pytest.approx(0.5), "torque": ""}


def test_a_torque_past_its_limit_is_named():
    limits = np.array([1.5, 1.5, 0.5])
    torque = np.zeros((5, 12))
    torque[1, 8] = 0.8  # HL's ankle servo
    out = _torque(torque, limits)
    assert out["torque_ratio"] == pytest.approx(1.6)
    assert out["torque"] == "HL3 needs 0.80 N m, past its 0.50 N m"


def test_a_bend_tighter_than_fc_is_named():
    from ftfof.climb.metrics import _film

    assert _film(1.0 / 0.007, 0.006) == ""
    assert _film(1.0 / 0.004, 0.006) == "the film bent to 4.0 mm, tighter than fc = 6 mm"
