"""Controller export: the foot path sampled at a rate, with joint angles the leg reaches."""

import numpy as np
import pytest

from ftfof.evaluate.export import COLUMNS, ExportRateError, controller_trajectory
from ftfof.kinematics.legs import build_leg
from ftfof.trajectory.sampling import sample_feasible


@pytest.mark.parametrize("ctx_name", ["m3f", "mst_q"])
def test_joint_angles_reproduce_the_foot_path(ctx_name, request):
    ctx = request.getfixturevalue(ctx_name)
    policy, leg = ctx.policy, build_leg(ctx.robot.leg)
    X = sample_feasible(policy, 1, seed=4).X[0]
    out = controller_trajectory(policy, leg, X, rate_hz=250.0)
    T3 = policy.timing.T3
    assert out.table.shape == (int(np.floor(T3 * 250 + 1e-9)) + 1, len(COLUMNS))
    t = out.table[:, 0]
    np.testing.assert_allclose(np.diff(t), 1 / 250, rtol=1e-9)
    s = policy.sample(X[None], t)
    np.testing.assert_allclose(out.table[:, 1:3], s.position[0], atol=1e-12)
    np.testing.assert_allclose(out.table[:, 3:5], s.velocity[0], atol=1e-12)
    theta = out.table[:, 5:8]
    np.testing.assert_allclose(leg.forward(theta), s.position[0], atol=1e-9)  # IK round trip
    if ctx_name == "m3f":  # its Ppl box lies inside the planar leg's joint ranges
        assert out.within_joint_limits
    # joint rates agree with J(theta) dq = v in the foot plane
    J = leg.jacobian(theta)
    v = np.einsum("nij,nj->ni", J, out.table[:, 8:11])
    np.testing.assert_allclose(v, s.velocity[0], atol=1e-9)


def test_unreachable_point_is_named(m3f):
    X = sample_feasible(m3f.policy, 1, seed=4).X[0].copy()
    X[6:9] = 5.0  # P3z..P5z five metres from the wall
    with pytest.raises(ValueError, match="cannot reach") as raised:
        controller_trajectory(m3f.policy, build_leg(m3f.robot.leg), X, 100.0)
    assert not isinstance(raised.value, ExportRateError)  # not the rate's fault


def test_a_rate_too_low_for_three_samples_is_the_rates_fault(m3f):
    X = sample_feasible(m3f.policy, 1, seed=4).X[0]
    with pytest.raises(ExportRateError, match="fewer than 3 samples"):
        controller_trajectory(m3f.policy, build_leg(m3f.robot.leg), X, 0.5)
