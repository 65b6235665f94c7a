"""The joint targets: how an anchored foot's target follows the body; the servos' targets on
the gait, pressed, and kept where a foot is out of reach."""

from __future__ import annotations

import numpy as np

from ftfof.climb.targets import Anchors, JointTargets, hip_frame

HIP = 0.03
HIPS = np.array([0.1, 0.1, -0.1, -0.1])
FR = np.array([False, True, False, False])
NO_FADE = np.zeros(4)


def _on_wall(targets: np.ndarray, planned: float, actual: float) -> np.ndarray:
    """Where a servo holding ``targets`` (gait targets with the body on its plan ``planned``)
    puts each foot along the wall with the body at ``actual``."""
    rel, _ = hip_frame(targets, np.zeros_like(targets), planned, 0.0, HIP, HIPS)
    return rel[:, 0] + actual + HIPS - HIP


def test_an_anchored_foot_stays_where_it_was_on_the_wall_as_the_body_sags():
    feet = np.stack([HIPS + 0.01, np.zeros(4)], axis=1)
    anchors = Anchors.none()
    sags = (-0.0014, -0.0034, -0.0021)  # the body's error from its plan, m
    placed = []
    for sag in sags:
        anchors = anchors.step(FR, NO_FADE, sag, 0.0)
        targets = feet.copy()
        targets[:, 0] += anchors.shift
        placed.append(_on_wall(targets, 0.2, 0.2 + sag))
    placed = np.array(placed)
    # FR is held where it was when anchored; the others ride on the body, as before
    np.testing.assert_allclose(placed[:, 1], placed[0, 1], atol=1e-15)
    np.testing.assert_allclose(placed[:, 0] - placed[0, 0], np.array(sags) - sags[0])
    assert anchors.shift[1] == -0.0014 - -0.0021  # shifted back by the sag since anchoring


def test_an_anchor_starts_from_zero_keeps_its_origin_and_each_foot_has_its_own():
    anchors = Anchors.none().step(FR, NO_FADE, -0.0014, -0.01)
    np.testing.assert_array_equal(anchors.shift, 0.0)  # no jump as the anchor begins
    np.testing.assert_array_equal(anchors.shift_v, [0.0, 0.01, 0.0, 0.0])  # against the body's
    anchors = anchors.step(FR, NO_FADE, -0.0034, 0.0)
    np.testing.assert_allclose(anchors.shift, [0.0, 0.002, 0.0, 0.0])
    two = np.array([True, True, False, False])
    anchors = anchors.step(two, NO_FADE, -0.0040, 0.0)
    np.testing.assert_allclose(anchors.shift, [0.0, 0.0026, 0.0, 0.0])
    assert anchors.origin[1] == -0.0014 and anchors.origin[0] == -0.0040


def test_a_released_foot_fades_its_shift_over_its_swing_instead_of_jumping():
    anchors = Anchors.none().step(FR, NO_FADE, -0.001, 0.0)
    anchors = anchors.step(FR, NO_FADE, -0.004, 0.0)  # held 3 mm back up the wall
    lifting = np.array([0.0, 1.0, 0.0, 0.0])
    anchors = anchors.step(np.zeros(4, dtype=bool), lifting, -0.0045, 0.0)
    # released: the shift it had as the anchor was let go, not the body's error since
    np.testing.assert_allclose(anchors.shift, [0.0, 0.0035, 0.0, 0.0])
    assert np.isnan(anchors.origin).all()
    anchors = anchors.step(np.zeros(4, dtype=bool), 0.5 * lifting, -0.001, 0.0)
    np.testing.assert_allclose(anchors.shift, [0.0, 0.00175, 0.0, 0.0])
    anchors = anchors.step(np.zeros(4, dtype=bool), NO_FADE, -0.001, 0.0)  # the swing is over
    np.testing.assert_array_equal(anchors.shift, 0.0)
    np.testing.assert_array_equal(anchors.released, 0.0)
    # a foot let go off the swing (its pad lost its bonds) drops its shift at once
    anchors = Anchors.none().step(FR, NO_FADE, -0.001, 0.0).step(FR, NO_FADE, -0.003, 0.0)
    np.testing.assert_array_equal(anchors.step(FR & False, NO_FADE, -0.003, 0.0).shift, 0.0)


def test_anchors_are_active_from_an_anchor_until_its_released_shift_has_faded():
    assert not Anchors.none().active
    anchors = Anchors.none().step(FR, NO_FADE, -0.001, 0.0)
    assert anchors.active
    anchors = anchors.step(FR, NO_FADE, -0.003, 0.0)
    lifting = np.array([0.0, 0.5, 0.0, 0.0])
    anchors = anchors.step(np.zeros(4, dtype=bool), lifting, -0.003, 0.0)
    assert anchors.active  # fading
    anchors = anchors.step(np.zeros(4, dtype=bool), NO_FADE, -0.003, 0.0)
    assert not anchors.active
    np.testing.assert_array_equal(anchors.shift, Anchors.none().shift)


def _targets(params):
    """Joint targets on the params' robot and gait (no Exudyn system: the targets need none)."""
    from types import SimpleNamespace

    from ftfof.climb.simulate import chain_of, gait_of
    from tests.climb.helpers import spec_of

    spec = spec_of(params)
    robot = SimpleNamespace(gait=gait_of(spec), chain=chain_of(spec.robot), q0=np.zeros(15))
    return JointTargets(robot), robot.gait, robot.chain


def test_the_servos_targets_put_each_foot_on_its_gait_target_and_a_press_into_the_wall(params):
    targets, gait, chain = _targets(params)
    t = gait.start + 0.5 * gait.swing  # the first swing, the body on its plan at 0
    press = np.array([0.0, 0.0, 0.0, 4e-4])
    for pressed in (np.zeros(4), press):
        assert targets.update(t, (t - gait.start, gait.leg_of(0)), (0.0, 0.0), gait.body,
                              pressed, None)  # fmt: skip
        theta = targets.offsets[3:].reshape(4, 3)
        feet, _ = gait.feet(t)
        rel, _ = hip_frame(feet, np.zeros((4, 2)), 0.0, 0.0, chain.hip[0], gait.hips)
        rel[:, 1] -= pressed
        np.testing.assert_allclose(chain.leg.forward(theta), rel, atol=1e-9)
    np.testing.assert_array_equal(targets.offsets[:3], 0.0)  # the floating base is not driven


def test_a_foot_out_of_reach_keeps_the_last_targets(params):
    targets, gait, _ = _targets(params)
    assert targets.update(0.0, (0.0, -1), (0.0, 0.0), gait.body, np.zeros(4), None)
    kept = targets.offsets.copy(), targets.rates.copy()

    def far(t):
        return np.full_like(t, 1.0), np.zeros_like(t)  # the body planned a metre up the wall

    assert not targets.update(0.0, (0.0, -1), (0.0, 0.0), far, np.zeros(4), None)
    np.testing.assert_array_equal(targets.offsets, kept[0])
    np.testing.assert_array_equal(targets.rates, kept[1])


def test_anchored_feet_shift_their_targets_by_the_bodys_error(params):
    targets, gait, _ = _targets(params)
    t = gait.start - 0.01  # before any swing: every foot on the wall
    assert targets.update(t, (0.0, -1), (0.0, 0.0), gait.body, np.zeros(4), FR)
    start = targets.offsets.copy()
    assert targets.update(t, (0.0, -1), (-0.002, 0.0), gait.body, np.zeros(4), FR)
    np.testing.assert_allclose(targets.anchors.shift, [0.0, 0.002, 0.0, 0.0])
    moved = np.any(targets.offsets != start, axis=None)
    assert moved and np.array_equal(targets.offsets[3:6], start[3:6])  # FL's target is its own
