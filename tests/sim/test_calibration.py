"""The calibrated default surface and foot against FTFOF Table I with the two baselines."""

from concurrent.futures import ProcessPoolExecutor

import pytest

from ftfof.sim.calibrate import TABLE_I
from ftfof.sim.simulate import simulate
from ftfof.trajectory.baselines import common_trajectories
from tests.sim.helpers import bench


def test_polynomial_and_cycloidal_baselines_come_within_15_percent_of_table_i(params, m3f):
    """The plate foot's fit meets the pre-pressures within 10 % and the peak detachments within
    15 %, on either side: it cannot order the pair as Table I does (the cycloid's steep lift
    fights the plate's turn about its toe; docs/decisions/0028)."""
    trajectories = common_trajectories(m3f.policy, params.baselines, params.base.seed)
    b = bench(params)
    specs = [b.analytic(f"baseline:{name}", 0, trajectories[name]) for name in TABLE_I]
    with ProcessPoolExecutor(2) as pool:
        results = list(pool.map(simulate, specs))
    measured = {}
    for name, result in zip(TABLE_I, results, strict=True):
        assert result.ok, result.error
        measured[name] = result.scalars["peak_detachment"]
        for quantity, target in TABLE_I[name].items():
            rel = 0.15 if quantity == "peak_detachment" else 0.10
            assert result.scalars[quantity] == pytest.approx(target, rel=rel), (name, quantity)
    assert measured["polynomial"] < measured["cycloidal"]  # Table I's order is the other way
