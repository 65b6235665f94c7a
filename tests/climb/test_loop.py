"""The climb loop's pure parts: how a yielding foot's joint target follows the body."""

from __future__ import annotations

import numpy as np

from ftfof.climb.loop import yield_shift


def test_a_yielding_foots_target_follows_the_bodys_error_since_it_began_to_yield():
    latch = np.full(4, np.nan)
    yielding = np.array([False, True, False, False])
    shift, shift_v, latch = yield_shift(yielding, latch, -0.0014, -0.01)
    # it starts where the foot is: no jump of the target when the yield begins
    np.testing.assert_array_equal(shift, 0.0)
    np.testing.assert_array_equal(shift_v, [0.0, -0.01, 0.0, 0.0])
    assert latch[1] == -0.0014 and np.isnan(latch[[0, 2, 3]]).all()
    # the body sags 2 mm more: the foot's target moves down with it, the others' stay
    shift, _, latch = yield_shift(yielding, latch, -0.0034, 0.0)
    np.testing.assert_allclose(shift, [0.0, -0.002, 0.0, 0.0])
    assert latch[1] == -0.0014  # kept while it yields
    # a second foot begins to yield: from where it is, with its own latch
    both = np.array([True, True, False, False])
    shift, _, latch = yield_shift(both, latch, -0.0040, 0.0)
    np.testing.assert_allclose(shift, [0.0, -0.0026, 0.0, 0.0])
    # the first lifts: its latch is cleared, its target is the gait's again
    shift, shift_v, latch = yield_shift(np.array([True, False, False, False]), latch, -0.004, 0.0)
    np.testing.assert_array_equal(shift, 0.0)
    assert np.isnan(latch[1]) and latch[0] == -0.0040
