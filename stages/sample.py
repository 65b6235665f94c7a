"""Stage `sample`: feasible foot trajectories for the selected robot -> data/trajectories."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated

import typer

from ftfof.files import write_parquet
from ftfof.pipeline.catalog import path
from ftfof.pipeline.summaries import write_metrics
from stages.common import ParamsOption, console, progress, stage

OUT = path("trajectories")
METRICS = path("sample_metrics")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    out: Annotated[Path, typer.Option(help="Trajectory table to write.")] = OUT,
    metrics: Annotated[Path, typer.Option(help="Summary metrics JSON.")] = METRICS,
) -> None:
    """Sample n climbable trajectories (scrambled Sobol or LHS over the rule-shaped region)."""
    from ftfof.data.sampled import sample_report, trajectory_table
    from ftfof.pipeline.bench import context_of
    from ftfof.pipeline.params_file import load_params
    from ftfof.seeds import seed_for
    from ftfof.trajectory.sampling import sample_feasible

    params = load_params(params_path)
    ctx = context_of(params)
    cfg = params.sample
    started = time.perf_counter()
    with progress(f"sample {ctx.name}") as bar:
        task = bar.add_task("sample", total=cfg.n, info="")

        def report(accepted: int, draws: int) -> None:
            bar.update(task, completed=accepted, info=f"{draws:,} draws")

        seed = seed_for(params.base.seed, "sample")
        result = sample_feasible(
            ctx.policy, cfg.n, seed, cfg.design, cfg.batch, cfg.max_draws, report
        )
    elapsed = time.perf_counter() - started
    write_parquet(out, trajectory_table(ctx, result.X))
    recheck = params.feasibility.recheck_hz
    write_metrics("sample", metrics, sample_report(ctx, result, cfg, recheck, elapsed))
    console.print(
        f"sampled {len(result.X)} trajectories for {ctx.name} from {result.draws:,} draws "
        f"(acceptance {result.acceptance_rate:.2e}) -> {out}"
    )
