"""The simulator's word on RHS candidates: re-simulate them on the platform and refuse those a
real foot would not survive, whatever the surrogates predicted (issue: film safety)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ftfof.config import Dataset, Optimize
from ftfof.data import targets
from ftfof.data.faults import foot_faults
from ftfof.evaluate.fidelity import simulated_objectives
from ftfof.optimize.select import SimulatorCheck, Verdict
from ftfof.robot import RobotContext
from ftfof.seeds import seed_for
from ftfof.sim.spec import Bench
from ftfof.trajectory.policy import ConstraintPolicy

if TYPE_CHECKING:
    from ftfof.sim.records import SampleResult

MEASURED = (
    "min_bend_radius",
    "peak_pull",
    "peak_normal",
    "peak_shear",
    "landing_pre_pressure",
    "peak_body_acc",
    "max_clearance",
    "switch_time",
    "rebond_fraction",
    "held_pull",
    "proof_held",
)


def perturbed_runs(
    policy: ConstraintPolicy, X: np.ndarray, error: float, copies: int, rng: np.random.Generator
) -> list[np.ndarray]:
    """A row's decision values, then ``copies`` copies with every free control value off by a
    normal error of ``error`` (m; fixed and tied values stay so). The copies are not kept in
    the box: the box is a rule of the commanded path, the error is the robot's. Clipped, a row
    on a bound (a peel straight up, P3x = P0x) was tested on one side only, half its draws
    there were no error at all, and the search could gain from sitting on it."""
    free = policy.contract(X)[0]
    return [X, *policy.expand(free + rng.normal(0.0, error, (copies, free.size)))]


def simulator_check(
    on: Bench,
    ctx: RobotContext,
    cfg: Optimize,
    dataset: Dataset,
    search_seed: int,
    workers: int,
) -> SimulatorCheck:
    """A check that simulates decision rows on the bench ``on`` (in parallel on ``workers`` local
    processes), each as it is and ``cfg.verify_copies`` times with every free control value off
    by a normal error of ``cfg.verify_repeatability``, with the robot's objectives (the mean over
    those runs) from the simulated forces (binned as the surrogate's targets). A row passes when
    every run of it passes: the run succeeds, the robot's rules hold (:mod:`ftfof.data.faults`:
    the pad lets go cleanly, the film stays at or above its safety limit, the landing presses
    within the robot's tolerance of a, the landed pad holds the proof pull where the robot asks
    for it, the body shakes no harder than the robot's limit) and
    every objective is finite."""
    force_t = targets.time_base(ctx.policy.timing.T3, dataset.hold, dataset.seq_len)
    return _Check(on, ctx, cfg, dataset.hold, force_t, search_seed, workers)


@dataclass(frozen=True, eq=False)
class _Check:
    """:func:`simulator_check`'s check: the runs of each row, simulated together, judged one by
    one and combined per row."""

    on: Bench
    ctx: RobotContext
    cfg: Optimize
    hold: float
    force_t: np.ndarray  # the surrogate targets' time base the objectives read
    search_seed: int
    workers: int

    def __call__(self, rows: Sequence[int], X: np.ndarray) -> list[Verdict]:
        if len(set(rows)) != len(rows):
            raise ValueError(f"the simulator check takes each row once (got {list(rows)})")
        runs = {row: self._runs_of(row, x) for row, x in zip(rows, X, strict=True)}
        # the nominal runs first: a row they refuse is refused whatever its copies do, so its
        # copies are not simulated (the same verdicts, a third of a refused row's runs)
        nominal = self._judged({(row, 0): xs[0] for row, xs in runs.items()})
        copies = self._judged(
            {
                (row, k): x
                for row, xs in runs.items()
                if nominal[row, 0].ok
                for k, x in enumerate(xs[1:], start=1)
            }
        )
        return [
            self._combine(row, [nominal[row, 0], *(copies[row, k] for k in range(1, len(xs)))])
            if nominal[row, 0].ok
            else nominal[row, 0]
            for row, xs in runs.items()
        ]

    def _runs_of(self, row: int, X: np.ndarray) -> list[np.ndarray]:
        rng = np.random.default_rng(seed_for(self.search_seed, "verify", row))
        cfg = self.cfg
        return perturbed_runs(self.ctx.policy, X, cfg.verify_repeatability, cfg.verify_copies, rng)

    def _judged(self, runs: dict[tuple[int, int], np.ndarray]) -> dict[tuple[int, int], Verdict]:
        """Each (row, run)'s verdict, the runs simulated together."""
        from ftfof.sim.pool import run_local

        specs = {(row, k): self.on.bezier(f"verify{k}", row, x) for (row, k), x in runs.items()}
        batches = run_local(list(specs.values()), self.workers) if specs else []
        done = {r.key: r for batch in batches for r in batch}
        return {
            (row, k): self._judge(row, runs[row, k], done[spec.key])
            for (row, k), spec in specs.items()
        }

    def _combine(self, row: int, verdicts: list[Verdict]) -> Verdict:
        """The row (its nominal run passed) passes when every copy passes; its objectives are
        the mean over the runs."""
        nominal, *copies = verdicts
        off_mm = 1e3 * self.cfg.verify_repeatability
        for k, copy in enumerate(copies, start=1):
            if not copy.ok:
                reason = (
                    f"with its control values off by N(0, {off_mm:.1f} mm) (copy {k}): "
                    f"{copy.reason}"
                )
                return Verdict(row, False, reason, nominal.measured)
        values = np.array([v.simulated for v in verdicts])
        spread = values.std(axis=0, ddof=1).tolist() if copies else []
        return Verdict(
            row, True, "", nominal.measured, values.mean(axis=0).tolist(), spread, len(verdicts)
        )

    def _judge(self, row: int, X: np.ndarray, result: SampleResult) -> Verdict:
        ctx = self.ctx
        measured = {k: float(result.scalars[k]) for k in MEASURED if k in result.scalars}
        if not result.ok:
            return Verdict(row, False, f"simulation failed: {result.error}", measured)
        c = result.channels
        faults = foot_faults(c["t"], c["bonds"], c["Fp"], measured, ctx.rules)
        measured["landing_held_pressure"] = faults.held_press
        if faults.release:
            pull = measured["peak_pull"]
            return Verdict(row, False, f"{faults.release} (peak pull {pull:.1f} N)", measured)
        if faults.first:
            return Verdict(row, False, faults.first, measured)
        objectives = simulated_objectives(
            ctx.robot.objectives,
            ctx.policy,
            X,
            [c],
            self.force_t,
            self.hold,
            ctx.robot.pre_pressure,
        )[0]
        broken = [
            n for n, v in zip(ctx.robot.objectives, objectives, strict=True) if not np.isfinite(v)
        ]
        if broken:
            return Verdict(row, False, f"no finite {', '.join(broken)} from its forces", measured)
        return Verdict(row, True, "", measured, [float(v) for v in objectives])
