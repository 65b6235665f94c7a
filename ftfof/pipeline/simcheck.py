"""The run's simulator check, built from its params (:mod:`ftfof.evaluate.simcheck`)."""

from __future__ import annotations

from ftfof.config import Params
from ftfof.evaluate.simcheck import simulator_check
from ftfof.optimize.select import SimulatorCheck
from ftfof.pipeline.bench import bench
from ftfof.robot import RobotContext


def simulator_check_of(params: Params, ctx: RobotContext) -> SimulatorCheck:
    """The run's simulator check (:func:`ftfof.evaluate.simcheck.simulator_check`)."""
    return simulator_check(
        bench(params, ctx),
        ctx,
        params.optimize,
        params.dataset,
        params.search_seed,
        params.acquire.workers,
    )
