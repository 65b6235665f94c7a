"""The landing verdict: the foot presses the pad to a within the robot's tolerance, at its peak
and still at the end of the landing hold."""

import numpy as np
import pytest

from ftfof.data.landing import HELD_WINDOW, held_press, landing_fault


def test_a_landing_within_the_tolerance_has_no_fault_on_either_side():
    assert landing_fault(5.0, 5.0, 5.0, 0.1) == ""
    assert landing_fault(4.5, 4.5, 5.0, 0.1) == ""  # the band's edges belong to it
    assert landing_fault(5.5, 5.2, 5.0, 0.1) == ""


def test_a_landing_that_misses_a_names_the_press_and_the_band():
    assert landing_fault(3.62, 3.6, 5.0, 0.1) == (
        "the landing pressed 3.62 N, outside a = 5.00 N ± 10 %"
    )
    assert landing_fault(5.6, 5.0, 5.0, 0.1).startswith("the landing pressed 5.60 N")


def test_an_impact_that_touches_a_and_sags_is_refused_on_the_held_press():
    assert landing_fault(5.1, 3.9, 5.0, 0.1) == "the landing held 3.90 N, outside a = 5.00 N ± 10 %"


def test_no_tolerance_requires_nothing():
    assert landing_fault(0.0, 0.0, 5.0, None) == ""


def test_the_held_press_is_the_mean_over_the_end_of_the_hold():
    t = np.arange(0.0, 1.25, 1e-3)
    Fp = np.where(t < 1.1, 6.0, 4.8)  # an impact, then the held press
    assert 1.25 - HELD_WINDOW > 1.1
    assert held_press(t, Fp, landing_hold=0.25) == pytest.approx(4.8)
    short = held_press(t, np.where(t < 1.2, 6.0, 4.8), landing_hold=0.02)
    assert short == pytest.approx(4.8)  # never reaches back past a short hold
