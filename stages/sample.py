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
    import numpy as np
    import pyarrow as pa

    from ftfof.data.schema import TRAJECTORIES
    from ftfof.pipeline.bench import context_of
    from ftfof.pipeline.params_file import load_params
    from ftfof.seeds import seed_for
    from ftfof.trajectory.bezier import DECISION_NAMES
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
    n = len(result.X)
    timing = ctx.robot.timing
    columns = {
        "sample_id": np.arange(n, dtype=np.int64),
        "robot": [ctx.name] * n,
        **{name: result.X[:, j] for j, name in enumerate(DECISION_NAMES)},
        "T1": np.full(n, timing.T1),
        "T2": np.full(n, timing.T2),
        "T3": np.full(n, timing.T3),
        "P15x": np.full(n, ctx.policy.p15[0]),
        "P15z": np.full(n, ctx.policy.p15[1]),
    }
    table = pa.Table.from_pydict(columns, schema=TRAJECTORIES)
    write_parquet(out, table)
    summary = {
        "robot": ctx.name,
        "samples": n,
        "draws": result.draws,
        "acceptance_rate": result.acceptance_rate,  # per draw over the rule-shaped region
        "box_acceptance_rate": result.box_acceptance,  # estimated, per plain box draw
        "rejected_by_fine_recheck": result.rejected_by_fine_recheck,
        "recheck_hz": params.feasibility.recheck_hz,
        "design": cfg.design,
        "free_variables": list(ctx.policy.free_names),
        "rejected_by_constraint": result.rejected_by,
        "rejected_by_kind": result.rejected_by_kind,
        # sampled-trajectory rules run only on the draws that pass the control-point rules
        "evaluated_by_constraint": result.evaluated_by,
        "pass_fraction_by_constraint": result.pass_fraction,
        "limits": ctx.limits.summary(),
        "seconds": round(elapsed, 3),
    }
    write_metrics("sample", metrics, summary)
    console.print(
        f"sampled {n} trajectories for {ctx.name} from {result.draws:,} draws "
        f"(acceptance {result.acceptance_rate:.2e}) -> {out}"
    )
