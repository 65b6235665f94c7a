"""The solver's step while the pad detaches: the check step evaluate re-simulates Table I with is
converged on every figure the objectives read, and the pull already is at the acquisition step."""

from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from ftfof.evaluate.step_check import CHECKED, checked_figures
from ftfof.sim.simulate import simulate
from ftfof.trajectory.baselines import Polynomial
from tests.sim.helpers import PUBLISHED, bench

pytestmark = pytest.mark.integration


def test_the_check_step_is_within_5_percent_of_half_of_it(params):
    check = params.evaluate.check_step
    steps = (params.acquire.solver.step, check, check / 2)
    poly = Polynomial(np.array([0.12, 0.0]), params.baselines.lift_height, 1.0)
    specs = []
    for k, h in enumerate(steps):
        b = bench(params, solver={"step": h})
        specs += [b.analytic("poly", k, poly), b.bezier("pf", k, PUBLISHED)]
    with ProcessPoolExecutor(2) as pool:
        results = list(pool.map(simulate, specs))
    assert all(r.ok for r in results), [r.error for r in results]
    T3 = params.selected_robot.timing.T3
    names = [c for c, _, _ in CHECKED]
    figures = np.array(
        [[checked_figures(r.channels, r.scalars, T3)[c] for c in names] for r in results]
    ).reshape(3, 2, len(names))  # (step, trajectory, figure)
    np.testing.assert_allclose(figures[1], figures[2], rtol=0.05)
    pull = names.index("peak_pull")
    np.testing.assert_allclose(figures[0, :, pull], figures[2, :, pull], rtol=0.05)
