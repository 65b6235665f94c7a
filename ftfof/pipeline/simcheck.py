"""The simulator's word on RHS candidates: re-simulate them on the platform and refuse those a
real foot would not survive, whatever the surrogates predicted (issue: film safety)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ftfof.config import Params
from ftfof.data import targets
from ftfof.data.release import release_fault
from ftfof.evaluate.fidelity import simulated_objectives
from ftfof.optimize.select import SimulatorCheck, Verdict
from ftfof.pipeline.bench import bench
from ftfof.robot import RobotContext

MEASURED = (
    "min_bend_radius",
    "peak_pull",
    "peak_normal",
    "peak_shear",
    "landing_pre_pressure",
    "peak_body_acc",
    "max_clearance",
    "switch_time",
)


def simulator_check(params: Params, ctx: RobotContext) -> SimulatorCheck:
    """A check that simulates decision rows (in parallel on ``acquire.workers`` local processes),
    each with the robot's objectives from its simulated
    forces (binned as the surrogate's targets), and passes it when the run succeeds, the pad lets go
    cleanly (:func:`ftfof.data.release.release_fault`: the switch trips, the whole pad rises
    ``foot.swing_clearance`` above the wall and stays off it until the landing) and the film's
    minimum bend radius stays at or above its safety limit (:class:`ftfof.sim.film.FilmLimit`)."""
    from ftfof.sim.film import film_limit
    from ftfof.sim.pool import run_local
    from ftfof.sim.records import SampleResult

    on = bench(params, ctx)
    d = params.dataset
    force_t = targets.time_base(ctx.policy.timing.T3, d.hold, d.seq_len)
    limit = film_limit(ctx.robot, params.selected_surface).radius
    clearance = ctx.robot.foot.swing_clearance
    landing_start = ctx.policy.timing.T2

    def check(rows: Sequence[int], X: np.ndarray) -> list[Verdict]:
        specs = [on.bezier("verify", row, x) for row, x in zip(rows, X, strict=True)]
        done = {r.key: r for batch in run_local(specs, params.acquire.workers) for r in batch}
        return [judge(row, x, done[s.key]) for row, x, s in zip(rows, X, specs, strict=True)]

    def judge(row: int, X: np.ndarray, result: SampleResult) -> Verdict:
        measured = {k: float(result.scalars[k]) for k in MEASURED if k in result.scalars}
        if not result.ok:
            return Verdict(row, False, f"simulation failed: {result.error}", measured)
        c = result.channels
        fault = release_fault(
            c["t"],
            c["bonds"],
            measured["switch_time"],
            measured["max_clearance"],
            clearance,
            landing_start,
        )
        if fault:
            pull = measured["peak_pull"]
            return Verdict(row, False, f"{fault} (peak pull {pull:.1f} N)", measured)
        bend = measured["min_bend_radius"]
        if bend < limit:
            return Verdict(
                row,
                False,
                f"film bent to {1e3 * bend:.2f} mm, below its {1e3 * limit:.2f} mm limit",
                measured,
            )
        objectives = simulated_objectives(
            ctx.robot.objectives, ctx.policy, X, [c], force_t, d.hold, ctx.robot.pre_pressure
        )[0]
        return Verdict(row, True, "", measured, [float(v) for v in objectives])

    return check
