"""The climb's force controller on a still robot: what each composition does when a foot slips."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.climb.control.controllers import compose
from ftfof.climb.control.feedforward import (
    CONTROL_RATE_HZ,
    FORCE_TIME_CONSTANT,
    MAX_TRIM,
    FeedForward,
    Pads,
)
from ftfof.climb.control.slip import SlipDetector
from ftfof.climb.legs import sagittal_chain
from ftfof.climb.simulate import pull_off_of
from ftfof.config.stages import Climb
from ftfof.sim.bonds import BondLaw
from ftfof.sim.slip import adhesion_truth
from tests.climb.control.stances import ADHESION, FRICTION, MASS, PULL_OFF, STROKE

CLIMB = Climb()
SLIP_HOLD = CLIMB.slip_hold
SLIDING = np.array([0.0, 0.05, 0.0, 0.0])  # FR slides up its patch at 50 mm/s


def _controller(m3f, name, replanner=lambda request: None):
    robot = m3f.robot
    chain = sagittal_chain(robot.leg, robot.climber.torque_limits, robot.platform.foot.ankle_height)
    pads = Pads(np.full(4, FRICTION), np.full(4, ADHESION), np.full(4, PULL_OFF))
    detector = SlipDetector(threshold=CLIMB.slip_threshold, hold=SLIP_HOLD)
    parts = compose(name, 4, replanner)
    controller = FeedForward(chain, MASS, 1e-3, float(chain.hip[1]), pads, detector, *parts)
    return controller, chain


def _plan(t):
    return np.zeros_like(t), np.zeros_like(t)


def _window(leg):
    fn = np.linspace(-2.0, 4.0, 15)  # the foot's press varies while it slides
    return fn, 0.3 * (fn + 5.0)  # a pad of mu 0.3, F_adh 5 N


def _run(controller, chain, velocity, steps, window=_window, stance=None):
    stance = np.ones(4, dtype=bool) if stance is None else stance
    theta = chain.leg.inverse(np.stack([STROKE, np.zeros(4)], axis=1))
    spacing = 0.2
    feet = STROKE + np.array([spacing, spacing, -spacing, -spacing]) / 2 - chain.hip[0]
    out = None
    for k in range(steps):
        out = controller.step(
            k / CONTROL_RATE_HZ,
            np.zeros(3),
            np.zeros(3),
            _plan,
            theta,
            feet,
            stance,
            velocity,
            window,
        )
    return out


def test_hanging_still_the_qp_gives_every_servo_a_finite_torque(m3f):
    controller, chain = _controller(m3f, "none")
    torques, plan = _run(controller, chain, np.zeros(4), 3)
    assert np.isfinite(torques).all() and np.abs(torques).max() > 0 and plan is None
    assert controller.counts.solves == 3 and controller.counts.slips == 0


def test_replan_estimates_the_slipping_pad_and_tracks_the_plan_it_is_given(m3f):
    seen = []

    def replanner(request):
        seen.append(request)
        return _plan

    controller, chain = _controller(m3f, "replan", replanner)
    steps = round(SLIP_HOLD * CONTROL_RATE_HZ) + 2
    _, plan = _run(controller, chain, SLIDING, steps)
    assert plan is None  # given once, on the slip's first step, and then kept by the loop
    assert len(seen) == 1 and seen[0].foot == 1
    assert seen[0].friction[1] == pytest.approx(0.3, rel=0.05)
    assert seen[0].friction[0] == FRICTION  # the others stay nominal
    assert controller.counts.estimates == 1 and controller.counts.replans == 1


@pytest.mark.parametrize("name", ["none", "weights"])
def test_without_replanning_the_slip_is_estimated_for_the_record_and_not_believed(m3f, name):
    controller, chain = _controller(m3f, name)
    steps = round(SLIP_HOLD * CONTROL_RATE_HZ) + 2
    _run(controller, chain, SLIDING, steps)
    assert controller.counts.slips == 1 and controller.counts.estimates == 0
    (record,) = controller.estimates
    assert record.foot == 1 and record.time == pytest.approx(SLIP_HOLD - 1 / CONTROL_RATE_HZ)
    # the tangential form: F_adh in N of shear, mu times the cone's 5 N shift
    assert record.fit.mu == pytest.approx(0.3, rel=0.05)
    assert record.fit.adhesion == pytest.approx(1.5, rel=0.05)
    assert np.all(controller.believed.friction == FRICTION)
    assert np.all(controller.believed.adhesion == ADHESION)


def test_the_recorded_estimate_changes_no_force(m3f):
    """The passive estimate is a record: a `none` climb's torques are those of a controller
    whose forces never reach an estimate (the foot still, no slip declared)."""
    steps = round(SLIP_HOLD * CONTROL_RATE_HZ) + 5
    sliding, chain = _controller(m3f, "none")
    still, _ = _controller(m3f, "none")
    torques, _ = _run(sliding, chain, SLIDING, steps)
    assert np.array_equal(torques, _run(still, chain, np.zeros(4), steps)[0])
    assert len(sliding.estimates) == 1 and not still.estimates


def test_adapted_weights_hold_through_the_phase_after_the_slip_stops_and_reset_with_it(m3f):
    controller, chain = _controller(m3f, "weights")
    steps = round(SLIP_HOLD * CONTROL_RATE_HZ) + 2
    _run(controller, chain, SLIDING, steps)
    rate = controller.adaptation.held_rate.copy()
    assert rate[1] > 0 and rate[[0, 2, 3]].sum() == 0
    sliding_torques, _ = _run(controller, chain, np.zeros(4), 1)
    # the slide stopped: the weights stay adapted
    assert controller.adaptation.held_rate[1] == rate[1]
    nominal, _ = _run(_controller(m3f, "weights")[0], chain, np.zeros(4), 1)
    assert not np.allclose(sliding_torques, nominal)
    lifted = np.array([True, True, True, False])  # HR lifts: a new phase
    _run(controller, chain, np.zeros(4), 1, stance=lifted)
    assert controller.adaptation.held_rate.sum() == 0


def test_replan_believes_what_a_peeling_pad_still_holds_where_its_mu_fit_is_negative(m3f):
    """f_t and f_n falling together (a pad losing its bonds as it slides) fit mu < 0: the pad
    keeps its believed mu and gets the adhesion it showed, so the QP unloads it."""

    def peel(leg):
        fn = np.linspace(-3.8, -0.5, 15)
        return fn, FRICTION * (fn + np.linspace(10.0, 2.0, 15))

    seen = []
    controller, chain = _controller(m3f, "replan", lambda request: seen.append(request))
    _run(controller, chain, SLIDING, round(SLIP_HOLD * CONTROL_RATE_HZ) + 2, peel)
    assert controller.counts.estimates == 1 and len(seen) == 1
    assert seen[0].friction[1] == FRICTION
    assert seen[0].adhesion[1] == pytest.approx(6.0, rel=1e-9)
    assert seen[0].adhesion[0] == ADHESION
    # the pull-off and F_adh are one bond strength seen two ways: they scale together
    assert controller.believed.pull_off[1] == pytest.approx(PULL_OFF * 6.0 / ADHESION)
    assert controller.believed.pull_off[0] == PULL_OFF


def _unloaded(leg):
    return np.zeros(15), np.zeros(15)  # the pads report no force: the servos miss all of it


def test_the_force_trim_integrates_what_the_pads_miss_of_the_qp_forces(m3f):
    controller, chain = _controller(m3f, "none")
    _run(controller, chain, np.zeros(4), 1, _unloaded)
    first = controller.trim.copy()  # the QP's forces times dt / FORCE_TIME_CONSTANT
    assert np.abs(first).max() > 0
    _run(controller, chain, np.zeros(4), 1, _unloaded)
    assert controller.trim == pytest.approx(2 * first, rel=1e-6)  # still: the same QP each step
    steps = round(4 * FORCE_TIME_CONSTANT * CONTROL_RATE_HZ)
    _run(controller, chain, np.zeros(4), steps, _unloaded)
    trim = controller.trim
    assert np.abs(trim).max() == pytest.approx(MAX_TRIM)  # bounded, not wound up
    assert np.all(np.sign(trim) == np.sign(first))


def test_the_force_trim_stays_zero_until_the_pads_have_a_sensor_window(m3f):
    controller, chain = _controller(m3f, "none")
    _run(controller, chain, np.zeros(4), 3, lambda leg: None)
    assert not controller.trim.any()


@pytest.mark.parametrize("name", ["acrylic", "glass", "painted_wall"])
def test_a_pads_pull_off_is_its_normal_strength_one_over_k_of_its_f_adh(params, name):
    surface = params.surfaces[name]
    law = BondLaw.from_surface(surface, 1e-3)
    area, preload = 1e-3, 5.0
    pull_off = pull_off_of(law, surface, preload, area)
    ratio = 1.0 / surface.shear_capacity_ratio  # F_adh,0 = phi tau A, tau = k sigma
    assert pull_off == pytest.approx(ratio * adhesion_truth(law, preload, area), rel=1e-12)


def test_the_stance_balances_what_a_foot_off_it_measures_the_landing_press(m3f):
    """FL in its landing hold presses 5 N (its pad's sensor): the stance feet's forces take it,
    their normal forces summing to -5 N, and the trunk still gets the planned wrench."""

    def pressing(leg):
        return (np.full(15, 5.0), np.zeros(15)) if leg == 0 else None

    controller, chain = _controller(m3f, "none")
    theta = chain.leg.inverse(np.stack([STROKE, np.zeros(4)], axis=1))
    feet = STROKE + np.array([0.1, 0.1, -0.1, -0.1]) - chain.hip[0]
    stance = np.array([False, True, True, True])
    sums = []
    for window in (lambda leg: None, pressing):
        torques, _ = controller.step(
            0.0, np.zeros(3), np.zeros(3), _plan, theta, feet, stance, np.zeros(4), window
        )
        pairs = zip(chain.leg.jacobian(theta[1:]), torques[1:], strict=True)
        forces = [np.linalg.lstsq(-J.T, tau, rcond=None)[0] for J, tau in pairs]
        sums.append(sum(f[1] for f in forces))
    assert sums[0] == pytest.approx(0.0, abs=1e-3)
    assert sums[1] == pytest.approx(-5.0, abs=1e-3)


def test_replan_believes_no_pad_whose_fit_holds_less_than_nothing(m3f):
    """A slide pressed on a cone whose apex lies past zero (the fit: mu 0.4, F_adh -5 N) is off
    the physical range: its F_adh fitted at the believed mu is negative too, so the pad's
    belief stays, and no re-planner is asked (it got a negative F_adh in a climb before)."""

    def pressed(leg):
        fn = np.linspace(6.0, 10.0, 15)
        return fn, 0.4 * (fn - 5.0)

    seen = []
    controller, chain = _controller(m3f, "replan", lambda request: seen.append(request))
    _run(controller, chain, SLIDING, round(SLIP_HOLD * CONTROL_RATE_HZ) + 2, pressed)
    assert controller.counts.slips == 1 and controller.counts.estimates == 0 and not seen
    assert np.all(controller.believed.adhesion == ADHESION)


@pytest.mark.parametrize("name", ["weights", "both"])
def test_a_slipping_foot_is_anchored_under_weight_adaptation_until_it_lifts(m3f, name):
    controller, chain = _controller(m3f, name)
    steps = round(SLIP_HOLD * CONTROL_RATE_HZ) + 2
    _run(controller, chain, np.zeros(4), steps)
    assert not controller.anchored.any()  # nothing slid
    _run(controller, chain, SLIDING, steps)
    assert controller.anchored.tolist() == [False, True, False, False]
    _run(controller, chain, np.zeros(4), 1)
    assert controller.anchored[1]  # the slide stopped: FR is still anchored
    _run(controller, chain, np.zeros(4), 1, stance=np.array([True, True, True, False]))
    assert controller.anchored[1]  # HR lifted, a new phase: FR's weights reset, it stays anchored
    assert controller.adaptation.held_rate.sum() == 0
    _run(controller, chain, np.zeros(4), 1, stance=np.array([True, False, True, True]))
    assert not controller.anchored.any()  # FR lifted


@pytest.mark.parametrize("name", ["none", "replan"])
def test_without_weight_adaptation_no_foot_is_anchored(m3f, name):
    controller, chain = _controller(m3f, name)
    _run(controller, chain, SLIDING, round(SLIP_HOLD * CONTROL_RATE_HZ) + 2)
    assert controller.counts.slips == 1 and not controller.anchored.any()
