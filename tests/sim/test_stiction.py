"""Stiction of the contact law in the simulator: a pressed pad held at half its cone stays put
(issue 51: the old tanh friction let a pressed pad creep under any shear)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ftfof.sim import slip
from ftfof.sim.identified import PROTOCOL
from ftfof.sim.slip import adhesion_truth
from ftfof.sim.spec import Bench
from ftfof.trajectory.bezier import Samples
from ftfof.trajectory.piecewise import PiecewiseQuintic

MOVE, HOLD = 0.1, 1.0  # s: the drive moves to its hold, then holds still
CHAIN = 2.0e4  # N/m of the drive's leg and mount: 1e4 N/m in series, a soft, force-like hold


def _move_and_hold(x: float) -> PiecewiseQuintic:
    t = np.array([0.0, MOVE, MOVE + HOLD])
    pos = np.stack([np.array([0.0, x, x]), np.zeros(3)], axis=-1)[None]
    zero = np.zeros_like(pos)
    return PiecewiseQuintic.from_samples(Samples(t, pos, zero, zero))


def _break_all(pad) -> None:
    """Every bond of ``pad`` broken (friction alone), as the pre-step would push it."""
    pad.state.broken[:] = True
    for obj, scale in zip(pad.parts.bonds, pad.state.scale, strict=True):
        pad.mbs.SetObjectParameter(obj, "damping", [1.0, float(scale), 0.0])


@pytest.mark.integration
@pytest.mark.parametrize("bonded", [True, False], ids=["bonded", "friction-alone"])
def test_a_pad_sheared_at_half_its_cone_does_not_creep(params, monkeypatch, bonded):
    """Pressed at the preload a, then pulled through a soft drive to half the quasi-static cone,
    0.5 (mu a + F_adh,0), and held: over the hold's last 0.5 s the film slides on the plate by
    less than 10 um/s (the drive's force falls by k_chain times the slip, so the pad sees a
    nearly constant shear, as under a stance foot). Friction alone (every bond broken, re-bond
    off): half of mu a, where the old regularised friction, mu N tanh(v / 1 mm/s), would slide
    at artanh(0.5) mm/s = 0.55 mm/s."""
    robot, surface = params.selected_robot, params.selected_surface
    if not bonded:
        surface = surface.model_copy(update={"rebond_pressure": 1e12})
    bench = Bench(robot, surface, params.platform, params.acquire, params.base.seed)
    law = slip.BondLaw.from_surface(surface, params.acquire.solver.contact_smoothing)
    adhesion = adhesion_truth(law, robot.pre_pressure, robot.pad_area) if bonded else 0.0
    cone = law.friction * robot.pre_pressure + adhesion
    traj = _move_and_hold(0.5 * cone * 2 / CHAIN)
    fixture = replace(PROTOCOL, loads=(robot.pre_pressure,), drive_stiffness=CHAIN)
    record: list[tuple[float, float]] = []
    step = slip._SlipStep.__call__

    def watched(self, mbs, t):  # the film's mean x on the plate after each pre-step
        if not (bonded or record):
            _break_all(self.pad)
        out = step(self, mbs, t)
        q = self.data.GetODE2Coordinates(copy=False)
        x = self.pad.parts.x_ref + q[self.pad.node_index] - q[self.pad.plate_index]
        record.append((t, float(np.mean(x))))
        return out

    monkeypatch.setattr(slip._SlipStep, "__call__", watched)
    log = slip.slip_test(bench.spec("slip", 0, traj), fixture, traj)
    held = log.t > log.t[-1] - 0.5
    assert np.mean(log.Fx[held]) == pytest.approx(0.5 * cone, rel=0.15)
    t, x = np.array(record).T
    late = t > t[-1] - 0.5
    rate = np.polyfit(t[late], x[late], 1)[0]
    assert abs(rate) < 10e-6, f"creeps {rate * 1e6:.2f} um/s at {np.mean(log.Fx[held]):.2f} N"
