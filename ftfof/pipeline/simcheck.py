"""The run's simulator check, built from its params (:mod:`ftfof.evaluate.simcheck`)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ftfof.config import Params
from ftfof.evaluate.simcheck import simulator_check
from ftfof.optimize.select import SimulatorCheck, Verdict
from ftfof.pipeline import interrupt
from ftfof.pipeline.bench import bench
from ftfof.robot import RobotContext


def simulator_check_of(params: Params, ctx: RobotContext) -> SimulatorCheck:
    """The run's simulator check (:func:`ftfof.evaluate.simcheck.simulator_check`); a stop
    request waits for the batch it is judging (a stop inside a simulation would be judged as
    that trajectory's failure)."""
    check = simulator_check(
        bench(params, ctx),
        ctx,
        params.optimize,
        params.dataset,
        params.search_seed,
        params.acquire.workers,
    )

    def judged(rows: Sequence[int], X: np.ndarray) -> list[Verdict]:
        with interrupt.deferred():
            verdicts = check(rows, X)
        interrupt.check()
        return verdicts

    return judged
