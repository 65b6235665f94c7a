"""The slip meter alone: each stance pad's slide is its film's travel on its wall patch."""

from __future__ import annotations

import numpy as np

from ftfof.climb.sensing import SlipMeter
from tests.climb.test_recorder import HANDLES, N


def test_each_stance_pads_slide_is_its_films_travel_on_its_patch_since_the_last_reading():
    meter = SlipMeter(HANDLES)
    stance = np.array([True, True, True, False])
    q = np.zeros(N)
    np.testing.assert_array_equal(meter.velocity(q, 0.1, stance, "control"), 0.0)
    q[[31, 35, 39, 43]] = 2e-5  # every pad's film node 20 um along the wall
    q[23] = 1e-5  # FL's plate moves along with half of it
    slide = meter.velocity(q, 0.102, stance, "control")
    np.testing.assert_allclose(slide, [5e-3, 1e-2, 1e-2, 0.0], rtol=1e-9)  # HR swings: 0
    # another reader's clock starts afresh; the first reader's has moved on
    np.testing.assert_array_equal(meter.velocity(q, 0.102, stance, "record"), 0.0)
    np.testing.assert_array_equal(meter.velocity(q, 0.104, stance, "control"), 0.0)
