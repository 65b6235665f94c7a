"""The calibrated default surface reproduces FTFOF Table I with the two baselines."""

from concurrent.futures import ProcessPoolExecutor

import pytest

from ftfof.sim.calibrate import TABLE_I
from ftfof.sim.simulate import simulate
from ftfof.trajectory.baselines import common_trajectories
from tests.sim.helpers import bench


def test_polynomial_and_cycloidal_baselines_match_table_i_within_10_percent(params, m3f):
    trajectories = common_trajectories(m3f.policy, params.baselines, params.base.seed)
    b = bench(params)
    specs = [b.analytic(f"baseline:{name}", 0, trajectories[name]) for name in TABLE_I]
    with ProcessPoolExecutor(2) as pool:
        results = list(pool.map(simulate, specs))
    for name, result in zip(TABLE_I, results, strict=True):
        assert result.ok, result.error
        for quantity, target in TABLE_I[name].items():
            assert result.scalars[quantity] == pytest.approx(target, rel=0.10), (name, quantity)
