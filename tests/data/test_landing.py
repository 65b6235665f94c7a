"""The landing verdict: the foot presses the pad to a within the robot's tolerance."""

from ftfof.data.landing import landing_fault


def test_a_landing_within_the_tolerance_has_no_fault_on_either_side():
    assert landing_fault(5.0, 5.0, 0.1) == ""
    assert landing_fault(4.5, 5.0, 0.1) == ""  # the band's edges belong to it
    assert landing_fault(5.5, 5.0, 0.1) == ""


def test_a_landing_that_misses_a_names_the_press_and_the_band():
    assert landing_fault(3.62, 5.0, 0.1) == "the landing pressed 3.62 N, outside a = 5.00 N ± 10 %"
    assert landing_fault(5.6, 5.0, 0.1).startswith("the landing pressed 5.60 N")


def test_no_tolerance_requires_nothing():
    assert landing_fault(0.0, 5.0, None) == ""
