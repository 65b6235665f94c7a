"""The proof pull after the landing hold (issue 53): the landed pad is pulled at its ankle to
F_proof by the platform's press loop, and the test stops as soon as a tenth of the pad lets go."""

from dataclasses import replace

import numpy as np
import pytest

from ftfof.demand import fore_foot_demand
from ftfof.seeds import seed_for
from ftfof.sim.simulate import simulate
from ftfof.trajectory.baselines import common_trajectories
from tests.sim.helpers import bench


@pytest.fixture
def polynomial(params, m3f):
    paths = common_trajectories(
        m3f.policy, params.baselines, seed_for(params.base.seed, "baselines")
    )
    return bench(params).analytic("baseline:polynomial", 0, paths["polynomial"])


def test_f_proof_is_the_fore_stance_demand_times_the_safety_factor(params, polynomial):
    robot = params.selected_robot
    assert polynomial.proof_pull == pytest.approx(
        robot.proof.safety_factor * fore_foot_demand(robot)
    )
    hold = params.platform.protocol
    assert polynomial.end_time == pytest.approx(
        polynomial.landing_end + hold.proof_ramp + hold.proof_hold
    )


def test_the_pull_leaves_the_step_s_record_and_figures_as_they_were(polynomial):
    """The proof pull runs after the landing hold: the channels still end there, and every
    figure of the step before it is the run's without the pull (to the bit up to the landing
    hold's last long step, 2 ms: the run that goes on takes the step there, not a long one; the
    last samples within 1e-5 of the channel's range)."""
    pulled, plain = simulate(polynomial), simulate(replace(polynomial, proof_pull=None))
    assert pulled.ok and plain.ok
    t = plain.channels["t"]
    early = t < t[-1] - 2 * polynomial.solver.phase_steps["landing_hold"]
    for name, values in plain.channels.items():
        np.testing.assert_array_equal(pulled.channels[name][early], values[early], err_msg=name)
        scale = 1e-5 * max(float(np.abs(values).max()), 1e-3)
        np.testing.assert_allclose(pulled.channels[name], values, rtol=0, atol=scale, err_msg=name)
    for name in ("peak_detachment", "peak_pull", "landing_pre_pressure", "peak_body_acc"):
        assert pulled.scalars[name] == pytest.approx(plain.scalars[name], rel=1e-6)
    assert np.isnan(plain.scalars["held_pull"]) and np.isnan(plain.scalars["proof_held"])
    assert pulled.scalars["rebond_fraction"] == plain.scalars["rebond_fraction"] == 1.0


def test_a_light_proof_holds_and_a_heavy_one_stops_at_the_tenth_let_go(polynomial):
    """Half the demand: the pad holds it through the hold, held_pull is F_proof. Twice it: a
    tenth of the pad lets go on the ramp, below F_proof, and the run ends there, ok (the test
    spares the rest of the pad): a stronger pull bears no more than the pad held."""
    demand = polynomial.proof_pull
    light = simulate(replace(polynomial, proof_pull=0.5 * demand))
    assert light.ok and light.scalars["proof_held"] == 1.0
    assert light.scalars["held_pull"] == pytest.approx(0.5 * demand)
    heavy = simulate(replace(polynomial, proof_pull=2.0 * demand))
    assert heavy.ok and heavy.scalars["proof_held"] == 0.0
    assert 0.5 * demand < heavy.scalars["held_pull"] < 2.0 * demand
    assert heavy.wall_time < light.wall_time  # it stopped at the let-go


def test_a_run_that_fails_in_the_pull_keeps_its_step_and_measures_no_pull(polynomial, monkeypatch):
    """The pull comes after the step's record: a solver failure inside it costs the pull's
    figures (NaN: the hold rule calls that not measured), not the step, and is not retried."""
    from ftfof.sim import proof

    pull = proof.ProofPull.__call__

    def failing(self, t, *args):
        if t > self.start + 0.05:
            raise RuntimeError("the solver gave up")
        return pull(self, t, *args)

    monkeypatch.setattr(proof.ProofPull, "__call__", failing)
    result = simulate(polynomial)
    assert result.ok and result.scalars["retries"] == 0.0
    assert np.isnan(result.scalars["held_pull"]) and np.isnan(result.scalars["proof_held"])
    assert result.channels["t"][-1] == pytest.approx(
        polynomial.landing_end - polynomial.trajectory_start
    )
