"""The solver's step: at one step throughout, the acquisition's is within 5 % of the check step
evaluate re-simulates Table I with on the pull, the body's jitter and the landing press, and
within 20 % on fs7's total, a count of the pull's second derivative passing its threshold: with
the 240 um film the polynomial's reads 11.89 / 11.78 / 10.39 at 500 / 250 / 125 us
(bench/step_convergence.py; 10.31 at 125 us after a 0.01 % change of sigma and p*), so a finer
acquisition step would not move it: the 125 us run is the odd one."""

from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from ftfof.evaluate.specs import with_step
from ftfof.evaluate.step_check import CHECKED, checked_figures
from ftfof.sim.simulate import simulate
from ftfof.trajectory.baselines import Polynomial
from tests.sim.helpers import PUBLISHED, bench

pytestmark = pytest.mark.integration


def test_the_acquisition_step_is_within_5_percent_of_the_check_step(params):
    solver = params.acquire.solver
    assert solver.free_step == solver.step  # a change of step within a run shakes the body
    b = bench(params)
    poly = Polynomial(np.array([0.12, 0.0]), params.baselines.lift_height, 1.0)
    acquisition = [b.analytic("poly", 0, poly), b.bezier("pf", 0, PUBLISHED)]
    check = [with_step(s, params.evaluate.check_step) for s in acquisition]
    with ProcessPoolExecutor(2) as pool:
        results = list(pool.map(simulate, acquisition + check))
    assert all(r.ok for r in results), [r.error for r in results]
    T3 = params.selected_robot.timing.T3
    names = [c for c, _, _ in CHECKED]
    figures = np.array(
        [[checked_figures(r.channels, r.scalars, T3)[c] for c in names] for r in results]
    ).reshape(2, 2, len(names))  # (step, trajectory, figure)
    rtol = np.array([0.20 if c == "force_jitter" else 0.05 for c in names])
    assert np.all(np.abs(figures[0] / figures[1] - 1) <= rtol), figures
