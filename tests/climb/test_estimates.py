"""The climb's slip estimates against the sliding pad's truth (issue 51): the truth is
identify's, on the preset the pad stands on at the slip; the summary is the median error."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ftfof.climb.control.slip import fit_pad
from ftfof.climb.control.state import SlipEstimate
from ftfof.climb.estimates import episodes, estimate_summary, pad_truth, slip_speed
from ftfof.climb.surface import SurfaceSwitch
from ftfof.identify.estimate import Estimate
from ftfof.sim.bonds import BondLaw
from ftfof.sim.identified import truth
from tests.climb.helpers import spec_of

HR, SWITCH = 3, 4.0
SPEED = 0.02  # m/s


@pytest.fixture(scope="module")
def spec(params):
    switch = SurfaceSwitch(HR, SWITCH, params.surfaces["dusty_wall"])
    return spec_of(params, "eps_bezier", switch=switch)


def _law(spec, surface):
    return BondLaw.from_surface(surface, spec.solver.contact_smoothing)


def test_the_truth_is_identifys_on_the_surface_the_pad_stands_on_then(spec):
    dusty, acrylic = _law(spec, spec.switch.surface), _law(spec, spec.surface)
    assert pad_truth(spec, HR, SWITCH + 0.1, SPEED) == truth(dusty, spec.robot, SPEED)
    assert pad_truth(spec, HR, SWITCH - 0.1, SPEED) == truth(acrylic, spec.robot, SPEED)
    assert pad_truth(spec, 0, SWITCH + 0.1, SPEED) == truth(acrylic, spec.robot, SPEED)
    moving, still = pad_truth(spec, HR, 5.0, SPEED), pad_truth(spec, HR, 5.0, 0.0)
    assert moving.mu == still.mu == spec.switch.surface.friction
    # F_adh(v) = R(v) F_adh,0: the rate factor at the slip's speed
    assert moving.adhesion == pytest.approx(dusty.drag_rate_factor(SPEED) * still.adhesion)
    assert moving.adhesion > still.adhesion


def _channels(v: float, at: float):
    t = np.arange(0.0, at + 0.05, 1e-3)
    velocity = np.zeros((t.size, 4))
    velocity[:, HR] = -v
    velocity[np.searchsorted(t, at - 0.1), HR] = -10 * v  # long before the window: not counted
    return {"t": t, "slip_velocity": velocity}


def test_the_slip_speed_is_the_median_over_the_estimators_window():
    c = _channels(SPEED, 5.0)
    c["slip_velocity"][np.searchsorted(c["t"], 5.0), HR] = -5 * SPEED  # one spike in it
    assert slip_speed(c["t"], c["slip_velocity"], HR, 5.0) == pytest.approx(SPEED)
    assert slip_speed(c["t"], c["slip_velocity"], 0, 5.0) == 0.0


def _sliding_window(pad: Estimate):
    """A pad sliding on its truth: f_t = mu f_n + F_adh, the press varying as it slides."""
    fn = np.linspace(0.2, 3.0, 15)
    return fn, -(pad.mu * fn + pad.adhesion)  # sliding down: the wall's friction is up


def test_a_pad_sliding_on_its_truth_is_estimated_with_no_error(spec):
    true = pad_truth(spec, HR, 5.0, SPEED)
    fit = fit_pad(*_sliding_window(true), "least_squares")  # exact on a noiseless slide
    (slip,) = episodes(spec, _channels(SPEED, 5.0), [SlipEstimate(5.0, HR, fit)])
    assert slip.truth == true and slip.speed == pytest.approx(SPEED)
    assert slip.errors == pytest.approx((0.0, 0.0), abs=1e-9)
    summary = estimate_summary([slip])
    assert summary["mu_error"] < 1e-9 and summary["adhesion_error"] < 1e-9
    assert summary["estimated_slips"] == 1.0


def test_wrong_estimates_give_their_relative_errors_and_the_summary_their_median(spec):
    true = pad_truth(spec, HR, 5.0, SPEED)
    wrong = [
        Estimate(2.0 * true.mu, 0.5 * true.adhesion),  # errors 1.0 and 0.5
        Estimate(0.9 * true.mu, 1.2 * true.adhesion),  # 0.1 and 0.2
        Estimate(-true.mu, 4.0 * true.adhesion),  # 2.0 and 3.0
    ]
    records = [SlipEstimate(5.0, HR, w) for w in wrong]
    slips = episodes(spec, _channels(SPEED, 5.0), records)
    errors = np.array([s.errors for s in slips])
    assert errors == pytest.approx(np.array([[1.0, 0.5], [0.1, 0.2], [2.0, 3.0]]))
    summary = estimate_summary(slips)
    assert summary["mu_error"] == pytest.approx(1.0) and summary["adhesion_error"] == 0.5
    row = slips[0].row()
    assert row["foot"] == "HR" and row["mu"]["truth"] == true.mu
    assert row["adhesion"]["error"] == pytest.approx(0.5)


def test_a_climb_without_slips_has_no_error_to_report():
    summary = estimate_summary([])
    assert math.isnan(summary["mu_error"]) and math.isnan(summary["adhesion_error"])
    assert summary["estimated_slips"] == 0.0
