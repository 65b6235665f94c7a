"""The landing press alone: the platform's integral loop drives a landed foot's press to the
pre-pressure a, from zero at each landing, and the press is released over the advance."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from ftfof.climb.press import LandingPress
from ftfof.sim.model import in_series
from ftfof.sim.press import PRESS_TIME_CONSTANT

SENSOR = SimpleNamespace(stiffness=2e5, damping=0.0)
PATH = 5e4  # N/m, the press path's stiffness up to the sensor
SERIES = in_series([PATH, SENSOR.stiffness])
GAIT = SimpleNamespace(swing=0.3, hold=0.25, shift=0.5)
PATCHES = np.array([0, 2, 4, 6], np.int64)
A = 3.0  # N, the pre-pressure


def _spring_plate(depth: np.ndarray) -> np.ndarray:
    """The sensor plates' coordinates (x, z per patch) under each foot's press ``depth`` through
    the path and the sensor in series: the plate gives way by the force over its stiffness."""
    q = np.zeros(8)
    q[PATCHES + 1] = -SERIES * depth / SENSOR.stiffness
    return q


def test_the_loop_drives_the_landed_foots_compression_to_the_pre_pressure():
    press = LandingPress(GAIT, SENSOR, PATCHES, A, SERIES)
    h = 0.2 * PRESS_TIME_CONSTANT
    for tau in np.arange(GAIT.swing, GAIT.swing + GAIT.hold, h):
        press.step(1, tau, _spring_plate(press.depth), np.zeros(8), h)
    compression = -SENSOR.stiffness * _spring_plate(press.depth)[PATCHES + 1]
    assert compression[1] == pytest.approx(A, rel=1e-9)
    np.testing.assert_array_equal(compression[[0, 2, 3]], 0.0)  # the other legs are not pressed
    held = press.depth[1]
    press.step(1, GAIT.swing + GAIT.hold, _spring_plate(press.depth * 0), np.zeros(8), h)
    assert press.depth[1] == held  # after the hold the depth stays, whatever the sensor reads
    press.step(1, 0.0, _spring_plate(press.depth), np.zeros(8), h)
    assert press.depth[1] == 0.0  # the next swing starts from zero


def test_the_press_is_released_over_the_advance():
    press = LandingPress(GAIT, SENSOR, PATCHES, A, PATH)
    press.depth[2] = 1e-4
    end_of_hold = GAIT.swing + GAIT.hold
    np.testing.assert_array_equal(press.applied(0.1, 2), [0.0, 0.0, 1e-4, 0.0])
    np.testing.assert_array_equal(press.applied(end_of_hold, 2), [0.0, 0.0, 1e-4, 0.0])
    taus = end_of_hold + np.linspace(0.0, GAIT.shift, 11)
    released = np.array([press.applied(tau, 2)[2] for tau in taus])
    assert np.all(np.diff(released) < 0) and released[-1] == 0.0
    assert released[5] == pytest.approx(5e-5)  # minimum jerk: half way at half the advance
    np.testing.assert_array_equal(press.applied(0.1, -1), 0.0)  # no step, no press


def test_springs_in_series_add_their_compliances():
    assert in_series([2.0, 2.0]) == 1.0
    assert in_series([3.0, np.inf]) == 3.0  # a rigid part (the grip foot's backing) drops out
