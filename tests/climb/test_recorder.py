"""The recorder alone: its channels tile a row, it records the state's readings at its rate,
drops rows past its buffer, and hands the controller the last recorded wall forces."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from ftfof.climb.control.feedforward import ESTIMATE_SAMPLES
from ftfof.climb.recorder import CHANNELS, Recorder, channel_slices
from ftfof.climb.sensing import Handles, SlipMeter

SENSOR = SimpleNamespace(stiffness=1e5, damping=10.0, plate_mass=0.01)
# coordinates: the tree's base and 12 joints (0-14), the feet (15-22), the plates (23-30), one
# film node per pad (31-46, four coordinates each)
HANDLES = Handles(
    tree=0,
    feet=np.arange(15, 23, 2),
    patches=np.arange(23, 31, 2),
    foot_ref=np.array([[0.1, 0.02], [0.1, 0.02], [-0.1, 0.02], [-0.1, 0.02]]),
    node_index=[np.array([31 + 4 * leg]) for leg in range(4)],
)
N = 47


def _recorder(end: float = 1.0, rate: float = 100.0) -> Recorder:
    robot = SimpleNamespace(spec=SimpleNamespace(platform=SimpleNamespace(sensor=SENSOR)),
                            gait=SimpleNamespace(end=end))  # fmt: skip
    broken = np.array([False, True, False])
    pads = [SimpleNamespace(state=SimpleNamespace(broken=broken)) for _ in range(4)]
    return Recorder(robot, HANDLES, pads, rate, SlipMeter(HANDLES))


def _plan(t):
    return np.full_like(t, 0.005), np.zeros_like(t)


def test_the_channels_tile_a_row():
    slices = list(channel_slices().values())
    assert [s.start for s in slices[1:]] == [s.stop for s in slices[:-1]]
    assert slices[0].start == 0 and slices[-1].stop == sum(w for _, w in CHANNELS)
    assert [s.stop - s.start for s in slices] == [w for _, w in CHANNELS]


def test_a_record_holds_the_states_readings():
    rec = _recorder()
    rng = np.random.default_rng(3)
    q, qd, qdd = (rng.normal(size=N) for _ in range(3))
    stance = np.array([True, True, False, True])
    torque = rng.normal(size=12)
    assert rec.due(0.0)
    rec.record(0.0, (q, qd, qdd), -1, stance, _plan, torque)
    assert rec.count == 1 and not rec.due(0.005) and rec.due(0.01)
    row = {name: rec.rows[0, s] for name, s in channel_slices().items()}
    np.testing.assert_array_equal(row["body"], q[:3])
    np.testing.assert_array_equal(row["body_acc"], qdd[:3])
    np.testing.assert_array_equal(row["body_plan"], 0.005)
    np.testing.assert_array_equal(row["joints"], q[3:15])
    np.testing.assert_array_equal(row["torque"], torque)
    np.testing.assert_array_equal(row["foot"][2:4], HANDLES.foot_ref[1] + q[17:19])
    plate_z = 26  # FR's plate z
    fz = SENSOR.stiffness * q[plate_z] + SENSOR.damping * qd[plate_z] + 0.01 * qdd[plate_z]
    assert row["force"][3] == pytest.approx(fz, rel=1e-15)
    np.testing.assert_array_equal(row["bonds"], 2.0)
    assert row["lowest"][1] == q[36] - q[plate_z]  # FR's film node z over its plate
    np.testing.assert_array_equal(row["curvature"], 0.0)  # nothing swings
    assert row["swing"][0] == -1
    np.testing.assert_array_equal(row["slip_velocity"], 0.0)  # the first reading has no rate
    q2 = q.copy()
    q2[35] += 1e-5  # FR's pad slides 10 um along its patch over the record
    rec.record(0.01, (q2, qd, qdd), -1, stance, _plan, torque)
    slip = rec.rows[1, channel_slices()["slip_velocity"]]
    np.testing.assert_allclose(slip, [0.0, 1e-3, 0.0, 0.0], rtol=1e-9)


def test_rows_past_the_buffer_are_dropped_and_the_clock_runs_on():
    rec = _recorder(end=0.0, rate=100.0)  # a buffer of 8 rows
    q = np.zeros(N)
    for k in range(10):
        rec.record(0.01 * k, (q, q, q), -1, np.ones(4, bool), _plan, np.zeros(12))
    assert rec.count == len(rec.rows) == 8
    assert rec.next_record == pytest.approx(0.1) and not rec.due(0.09)


def test_the_force_window_is_the_last_records_pressing_force_on_a_leg():
    rec = _recorder(end=10.0)
    forces = channel_slices()["force"]
    q = np.zeros(N)
    for k in range(ESTIMATE_SAMPLES + 3):
        rec.record(0.01 * k, (q, q, q), -1, np.ones(4, bool), _plan, np.zeros(12))
        rec.rows[k, forces] = k * np.arange(1.0, 9.0)  # Fx, Fz per leg, scaled by the record
        assert (rec.forces(2) is None) == (k + 1 < ESTIMATE_SAMPLES)
    f_n, f_t = rec.forces(2)
    recent = np.arange(3, ESTIMATE_SAMPLES + 3)
    np.testing.assert_array_equal(f_n, -6.0 * recent)  # HL's Fz, negated: pressing
    np.testing.assert_array_equal(f_t, -5.0 * recent)
