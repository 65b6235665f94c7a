"""The release verdict: a pad lets go cleanly, or the message says how it did not."""

import numpy as np

from ftfof.data.release import release_fault, swing_gap

TIME = np.arange(0.0, 1.0, 1e-3)
T2 = 0.6


def _bonds(rebond_at: float | None = None) -> np.ndarray:
    bonds = np.where(TIME < 0.3, 10.0, 0.0)
    if rebond_at is not None:
        bonds[rebond_at <= TIME] = 4.0
    return bonds


def test_a_clean_release_has_no_fault():
    assert release_fault(TIME, _bonds(), 0.32, 0.03, 0.009, T2) == ""
    assert release_fault(TIME, _bonds(rebond_at=0.8), 0.32, 0.03, 0.009, T2) == ""  # the landing


def test_each_way_of_not_letting_go_is_named():
    assert release_fault(TIME, _bonds(), float("nan"), 0.0015, 0.009, T2) == "the pad never let go"
    low = release_fault(TIME, _bonds(), 0.32, 0.004, 0.009, T2)
    assert low == "the pad rose only 4.0 mm above the wall (needs 9.0 mm)"
    touched = release_fault(TIME, _bonds(rebond_at=0.45), 0.32, 0.03, 0.009, T2)
    assert touched == "the pad touched the wall again in the swing at t = 0.450 s"


def test_the_swing_gap_is_the_lowest_clearance_from_first_rising_to_the_landing():
    t = np.linspace(0.0, 1.0, 11)
    clean = np.array([0, 0, 0, 0.01, 0.05, 0.04, 0.02, 0.01, 0.0, 0.0, 0.0])
    dips = clean.copy()
    dips[5] = 0.0  # touches the wall mid-swing
    early = np.array([0, 0.001, 0.0, 0.02, 0.05, 0.04, 0.02, 0.01, 0, 0, 0])  # before rising
    low = np.full(11, 0.004)  # never rises 9 mm
    gaps = swing_gap(np.stack([clean, dips, early, low]), t, 0.009, 0.75)
    np.testing.assert_allclose(gaps, [0.01, 0.0, 0.01, 0.0])
