"""The robot's rules on one simulated step, as the simulator check and the report both read them:
each fault named, told in the check's order, and a value the simulation did not give breaks its
rule instead of passing it."""

import numpy as np
import pytest

from ftfof.data.faults import foot_faults
from ftfof.rules import FootRules
from ftfof.sim.film import FilmLimit

TIME = np.arange(0.0, 1.3, 1e-3)
BONDS = np.where(TIME < 0.3, 10.0, np.where(TIME > 1.0, 10.0, 0.0))  # released, then landed
RULES = FootRules(
    film=FilmLimit(fc=0.0016, peel_root=0.0012),
    swing_clearance=0.009,
    detached=0.002,
    landing_start=0.6,
    pre_pressure=5.0,
    landing_tolerance=0.1,
    retouch_allowed=None,
    landing_hold=0.25,
    body_acc_limit=9.81,
)
GOOD = {
    "switch_time": 0.32,
    "max_clearance": 0.03,
    "min_bend_radius": 0.0022,
    "landing_pre_pressure": 5.1,
    "peak_body_acc": 6.0,
}


def _faults(press: float = 5.0, **scalars: float):
    Fp = np.where(TIME > 1.0, press, 0.0)
    return foot_faults(TIME, BONDS, Fp, {**GOOD, **scalars}, RULES)


def test_a_step_within_every_rule_is_clean_and_reports_the_held_press():
    faults = _faults(press=4.8)
    assert faults.clean and faults.first == ""
    assert faults.held_press == pytest.approx(4.8)


def test_each_rule_names_its_fault_and_the_first_is_told_in_the_check_s_order():
    faults = _faults(press=4.0, max_clearance=0.004, min_bend_radius=0.0012, peak_body_acc=12.0)
    assert faults.release == "the pad rose only 4.0 mm above the wall (needs 9.0 mm)"
    assert faults.film == "film bent to 1.20 mm, below its 1.60 mm limit"
    assert faults.landing == "the landing held 4.00 N, outside a = 5.00 N ± 10 %"
    assert faults.shake == "the body shook 12.0 m/s², above the robot's 9.81 m/s² limit"
    assert faults.first == faults.release and not faults.clean
    assert _faults(min_bend_radius=0.0012, peak_body_acc=12.0).first == faults.film
    assert _faults(peak_body_acc=12.0).first == faults.shake


@pytest.mark.parametrize(
    ("scalar", "rule"),
    [
        ("max_clearance", "release"),
        ("min_bend_radius", "film"),
        ("landing_pre_pressure", "landing"),
        ("peak_body_acc", "shake"),
    ],
)
def test_a_value_the_simulation_did_not_give_breaks_its_rule(scalar, rule):
    faults = _faults(**{scalar: float("nan")})
    assert getattr(faults, rule) and not faults.clean
    assert [name for name in ("release", "film", "landing", "shake") if getattr(faults, name)] == [
        rule
    ]


PROVED = FootRules(**{**RULES.__dict__, "proof_pull": 6.6})


def test_a_landed_pad_must_hold_the_proof_pull_to_the_end_of_its_hold():
    def hold(**scalars: float) -> str:
        Fp = np.where(TIME > 1.0, 5.0, 0.0)
        return foot_faults(TIME, BONDS, Fp, {**GOOD, **scalars}, PROVED).hold

    assert hold(proof_held=1.0, held_pull=6.6) == ""
    assert hold(proof_held=0.0, held_pull=4.96) == (
        "the landed pad let a tenth go at 4.96 N, below F_proof 6.60 N"
    )
    assert hold(proof_held=0.0, held_pull=6.6) == (
        "the landed pad bore F_proof 6.60 N, then let a tenth go in the hold"
    )
    assert hold() == "the landed pad's proof pull was not measured"  # a record without the phase
    # a robot whose rules ask for no proof pull judges no record by it
    assert _faults().hold == "" and _faults().clean


def test_the_hold_is_told_after_the_landing_and_before_the_shake():
    Fp = np.where(TIME > 1.0, 4.0, 0.0)
    scalars = {**GOOD, "peak_body_acc": 12.0, "proof_held": 0.0, "held_pull": 3.0}
    faults = foot_faults(TIME, BONDS, Fp, scalars, PROVED)
    assert faults.first == faults.landing
    faults = foot_faults(TIME, BONDS, np.where(TIME > 1.0, 5.0, 0.0), scalars, PROVED)
    assert faults.first == faults.hold and faults.shake
