"""climb.controller in the climb: off, it leaves the climb as it was; on, the QP drives the servos'
feed-forward and the robot still climbs; the slip figures are those of its channels."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from ftfof.climb.metrics import slip_totals, stance_travel
from ftfof.climb.simulate import climb
from tests.climb.helpers import spec_of
from tests.conftest import ROOT

pytestmark = pytest.mark.integration


def _one_step(params, controller):
    spec = spec_of(params)
    update = {"steps": 1, "controller": controller}
    return climb(replace(spec, climb=spec.climb.model_copy(update=update)))


@pytest.fixture(scope="module")
def off(params):
    return _one_step(params, None)


@pytest.fixture(scope="module")
def qp(params):
    return _one_step(params, "none")


def test_without_a_controller_the_climb_is_the_one_before_controllers(off):
    """Pinned from main before the controllers (b1dd8b9), re-pinned with the contact law of
    docs/decisions/0027, and re-pinned on the plate foot (decision 0028, a new foot: the body
    ends 0.70 mm further up, the torque and force sums 2.1 and 2.9 % lower): the polynomial's
    first step, 2001 records. Any feed-forward leaking into the servos moves these far past the
    tolerance."""
    c = off.channels
    assert off.control == {} and c["t"].size == 2001
    body = [0.02965494952719392, -0.00011180764708902903, 0.0007141117591752466]
    assert c["body"][-1] == pytest.approx(body, rel=1e-9)
    assert np.abs(c["torque"]).sum() == pytest.approx(2950.8696638813926, rel=1e-9)
    assert np.abs(c["force"]).sum() == pytest.approx(28951.667672309457, rel=1e-9)


def test_the_qp_drives_the_servos_and_the_robot_climbs_its_step(qp):
    assert qp.ok and not qp.fell
    assert qp.control["solves"] >= 2000 and qp.control["failed"] == 0
    assert qp.channels["body"][-1, 0] == pytest.approx(qp.gait.advance, rel=0.1)


def test_the_slip_figures_are_the_stance_pads_small_sway_when_nothing_slips(off, qp):
    """The slip figures come from each stance pad's film position on its patch, differenced over
    a record (loop._slip_velocity): the plate's stance film rings at the solver's step (FL's mean
    film velocity alternated +-4.82 mm/s from one 500 us step to the next), and integrating the
    velocity sampled every other step read that as a steady 4.8 mm/s slide, 12.3 mm of travel
    over the polynomial's first step with all 41 bonds intact, while the film's mean moved 10 um.
    A bonded stance pad travels no further than its foot, and nothing slips in one step."""
    c, gait = off.channels, off.gait
    for leg in range(4):  # a bonded stance pad cannot travel further than its foot, + 1 mm
        stance = np.ones(c["t"].size, bool)
        if leg == gait.leg_of(0):
            stance = c["t"] < gait.lift_off(0)
        foot = np.ptp(c["foot"][stance, 2 * leg])
        travel = np.abs(stance_travel(c["t"][stance], c["slip_velocity"][stance, leg])).max()
        assert travel <= foot + 1e-3, (leg, travel, foot)
    for run in (off, qp):
        totals = slip_totals(run.channels)
        assert (totals.distance >= 0).all() and (totals.peak >= 0).all()
        # nothing slips in one step: the pads' elastic sway on their patches, well under 1 mm
        assert totals.summary()["slip_distance"] < 1e-3
    gait, t = off.gait, off.channels["t"]
    held = (t >= gait.lift_off(0)) & (t < gait.lift_off(0) + gait.swing + gait.hold)
    assert np.all(off.channels["slip_velocity"][held, gait.leg_of(0)] == 0)  # off the stance


def test_a_controlled_climb_leaves_no_solver_for_the_interpreter_to_report(tmp_path):
    """Exudyn keeps the system, and so the controller's proxsuite QP, to the interpreter's end,
    where nanobind printed a leak report under every controlled `ftfof climb`."""
    script = (
        "from dataclasses import replace\n"
        "from ftfof.climb.simulate import climb\n"
        "from ftfof.pipeline.params_file import load_params\n"
        "from tests.climb.helpers import spec_of\n"
        "from tests.conftest import ROOT\n"
        "spec = spec_of(load_params(ROOT / 'params.yaml'))\n"
        "run = climb(replace(spec, climb=spec.climb.model_copy(update={'controller': 'none'})),"
        " duration=0.05)\n"
        "assert run.control['solves'] > 0\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    assert "leaked" not in done.stderr
