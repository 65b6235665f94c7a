"""Each preset's leg as the climbing robot's sagittal chain."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.climb.legs import sagittal_chain
from ftfof.kinematics.legs import build_leg


def test_a_planar_leg_is_its_own_chain(m3f):
    leg = m3f.robot.leg
    foot = m3f.robot.platform.foot
    chain = sagittal_chain(leg, (1.0, 1.0, 1.0), foot.ankle_height)
    preset = build_leg(leg)
    p = np.array([[0.0, 0.0], [0.06, 0.03], [0.12, 0.0]])
    assert chain.leg.inverse(p) == pytest.approx(preset.inverse(p))
    assert chain.preset_joints == (0, 1, 2)


def test_a_spatial_leg_keeps_its_pitch_and_knee_angles(mst_q):
    """The chain's angles are the ε-Bezier leg's pitch and knee, shifted by the radial axis; its
    reach moves by the ankle height replacing d4."""
    leg = mst_q.robot.leg
    ankle = mst_q.robot.platform.foot.ankle_height
    chain = sagittal_chain(leg, (1.0, 2.0, 3.0), ankle)
    preset = build_leg(leg)
    p = np.array([[0.0, 0.0], [0.03, 0.01], [0.065, -0.004]])
    theta = preset.inverse(p)
    mapped = chain.leg.inverse(p)
    assert mapped[:, 0] == pytest.approx(theta[:, 1] - np.pi / 2)
    assert mapped[:, 1] == pytest.approx(theta[:, 2])
    assert chain.leg.forward(mapped) == pytest.approx(p, abs=1e-12)
    assert chain.torque_limits[:2] == pytest.approx([2.0, 3.0]) and np.isinf(chain.torque_limits[2])


def test_the_stance_stroke_is_checked_against_the_joint_ranges(m3f, mst_q):
    from ftfof.climb.legs import stroke_breach

    foot = m3f.robot.platform.foot
    chain = sagittal_chain(m3f.robot.leg, (1.0, 1.0, 1.0), foot.ankle_height)
    assert stroke_breach(chain, m3f.robot.landing.x) == ""
    ahead = mst_q.robot.leg.model_copy(
        update={"hip": mst_q.robot.leg.hip.model_copy(update={"x": 0.02})}
    )
    chain = sagittal_chain(ahead, (1.0, 1.0, 1.0), foot.ankle_height)
    assert stroke_breach(chain, mst_q.robot.landing.x).endswith("joint range 0 mm along the wall")
