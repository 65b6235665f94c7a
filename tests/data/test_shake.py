"""The body-shake verdict: within the robot's limit, or a message naming both numbers."""

from ftfof.data.shake import shake_fault


def test_a_step_within_the_limit_or_without_one_passes():
    assert shake_fault(9.0, 9.81) == ""
    assert shake_fault(9.81, 9.81) == ""
    assert shake_fault(50.0, None) == ""


def test_a_harder_shake_names_the_peak_and_the_limit():
    assert shake_fault(21.3, 9.81) == "the body shook 21.3 m/s², above the robot's 9.81 m/s² limit"
