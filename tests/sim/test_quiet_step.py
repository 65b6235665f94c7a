"""The quiet-flight step (``acquire.solver.quiet_step``, docs/simulator.md, "A longer step in
quiet flight"): taken only while nothing sharp can happen, changed so that Exudyn's clock and
its integration agree (no kick to the body), and it leaves Table I where it was."""

import math
from typing import ClassVar

import numpy as np
import pytest
from pydantic import ValidationError

from ftfof.config.stages import Solver
from ftfof.sim import bonds, prestep
from ftfof.sim.simulate import simulate
from ftfof.trajectory.baselines import Polynomial
from tests.sim.helpers import PUBLISHED, bench

QUIET = 1e-3


def test_quiet_step_needs_one_step_elsewhere():
    Solver(step=5e-4, free_step=5e-4, quiet_step=1e-3)
    with pytest.raises(ValidationError, match="free_step == step"):
        Solver(step=5e-4, free_step=2e-3, quiet_step=1e-3)


def _specs(params, quiet_step):
    b = bench(params, solver={"quiet_step": quiet_step})
    poly = Polynomial(np.array([0.12, 0.0]), params.baselines.lift_height, 1.0)
    return [b.analytic("poly", 0, poly), b.bezier("pf", 0, PUBLISHED)]


class _Logged(prestep.PreStep):
    """The pre-step, recording each step's size and the pad's state at its start."""

    log: ClassVar[list[tuple[float, float, int, int, float, float]]] = []

    def __call__(self, mbs, t):
        go = super().__call__(mbs, t)
        st = self.pad.state
        active = int((~self.pad.idle).sum())
        switched = self.switched_at
        h = self.solver.it.currentStepSize
        lowest = self._lowest
        self.log.append((t, h, int((~st.broken).sum()), active, lowest, switched))
        return go

    def _quiet(self, t, q, qd, n_bonded, lowest):
        self._lowest = lowest
        return super()._quiet(t, q, qd, n_bonded, lowest)

    def _control_step(self, t, lam_max, lowest):
        self._lowest = lowest
        return super()._control_step(t, lam_max, lowest)


@pytest.fixture
def logged(monkeypatch):
    monkeypatch.setattr("ftfof.sim.simulate.PreStep", _Logged)
    _Logged.log = []
    return _Logged


@pytest.mark.integration
def test_without_quiet_step_every_step_is_the_step(params, logged):
    assert params.acquire.solver.quiet_step is None  # today's runs stay as they were
    result = simulate(_specs(params, None)[0])
    assert result.ok, result.error
    h = np.array([row[1] for row in logged.log])
    assert np.all(h[:-1] == params.acquire.solver.step)
    assert result.scalars["quiet_steps"] == 0


@pytest.mark.integration
def test_quiet_steps_only_in_quiet_flight(params, logged):
    """A quiet step starts with no bond, every bond connector off, the whole film above
    QUIET_HEIGHT, after the body jitter's window and before the trajectory ends; it ends with
    no bond and the film still clear of the plate; every other step is ``step``."""
    spec = _specs(params, QUIET)[0]
    result = simulate(spec)
    assert result.ok, result.error
    log = np.array(logged.log)
    t, h, bonded, active, lowest, switched = log.T
    quiet = np.isclose(h, QUIET, rtol=0, atol=1e-12)
    assert quiet.sum() == result.scalars["quiet_steps"] > 100
    assert np.all(np.isclose(h[~quiet][:-1], spec.solver.step, rtol=0, atol=1e-15))
    assert np.all(bonded[quiet] == 0) and np.all(active[quiet] == 0)
    assert np.all(lowest[quiet] > prestep.QUIET_HEIGHT)
    assert np.all(t[quiet] >= switched[quiet] + prestep.QUIET_AFTER_SWITCH)
    assert np.all(t[quiet] < spec.trajectory_start + spec.trajectory.duration)
    after = np.flatnonzero(quiet) + 1
    assert np.all(bonded[after] == 0) and np.all(lowest[after] > bonds.IDLE_HEIGHT)
    # the clock moved by the steps integrated: the run ends on its end time, one step a row
    assert math.isclose(t[-1], spec.end_time, abs_tol=1e-9)
    assert np.allclose(np.diff(t)[:-1], h[1:-1], rtol=0, atol=1e-12)


@pytest.mark.integration
def test_quiet_step_keeps_table_one_and_repeats(params):
    """Pull, detachment jitter and bend come out bit for bit (the quiet flight starts after
    them); the landing press, the run's peak body acceleration and the pad's clearance within
    0.1 %; no step change kicks the body (body_acc within 0.05 m/s² of one step throughout,
    where the old pre-step change kicked it by 2.5-3.5 m/s²); two runs are bit-identical."""
    one, quiet, again = ([simulate(s) for s in _specs(params, q)] for q in (None, QUIET, QUIET))
    for a, b, c in zip(one, quiet, again, strict=True):
        assert a.ok and b.ok and c.ok
        assert b.scalars["quiet_steps"] > 100
        for figure in ("peak_pull", "min_bend_radius", "switch_time"):
            assert b.scalars[figure] == a.scalars[figure]
        for figure in ("landing_pre_pressure", "peak_body_acc", "max_clearance"):
            assert b.scalars[figure] == pytest.approx(a.scalars[figure], rel=1e-3)
        first_break = np.flatnonzero(a.channels["bonds"] < a.channels["bonds"][0])[0]
        window = slice(first_break, np.flatnonzero(a.channels["switch"] > 0)[0] + 50)
        assert np.array_equal(a.channels["body_acc"][window], b.channels["body_acc"][window])
        assert np.max(np.abs(a.channels["body_acc"] - b.channels["body_acc"])) < 0.05
        assert all(np.array_equal(b.channels[k], c.channels[k]) for k in b.channels)
