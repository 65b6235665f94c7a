"""Stage `optimize`: NSGA-II on the surrogates, then one trajectory by RHS -> data/optimize/.

The choice is made among the front rows that pass a recheck on a finer time grid
(:mod:`ftfof.optimize.select`); the run is tracked live in MLflow (:mod:`ftfof.pipeline.optimize`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, progress, stage

MODELS = path("models")
OUT = path("optimize")
METRICS = path("optimize_metrics")
CONVERGENCE = path("optimize_convergence")
STAR = path("optimize_star")
PCP = path("optimize_pcp")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    models: Annotated[Path, typer.Option(help="Trained surrogate directory.")] = MODELS,
    out: Annotated[Path, typer.Option(help="Output directory (front, optimum).")] = OUT,
    metrics: Annotated[Path, typer.Option(help="Metrics JSON.")] = METRICS,
    convergence: Annotated[Path, typer.Option(help="Convergence CSV.")] = CONVERGENCE,
    star: Annotated[Path, typer.Option(help="Star-coordinate plot (Fig. 10).")] = STAR,
    pcp: Annotated[Path, typer.Option(help="Parallel-coordinate plot.")] = PCP,
) -> None:
    """Search the trajectory space with NSGA-II on the surrogates; choose one by RHS."""
    from ftfof.pipeline.optimize import OptimizeRun, Outputs, prepare
    from ftfof.pipeline.params_file import load_params

    params = load_params(params_path)
    setup = prepare(params, models)
    outputs = Outputs(out, metrics, convergence, star, pcp)
    with OptimizeRun(params, setup) as run, progress(f"optimize {setup.ctx.name}") as bar:
        task = bar.add_task("generations", total=params.optimize.generations, info="")

        def on_record(record) -> None:
            bar.update(
                task,
                completed=record.generation,
                info=f"feasible {record.feasible}, front {record.front}, "
                f"HV {record.hypervolume:.4f}",
            )

        result, outcome = run.search(on_record, outputs)
    opt = outcome.summary["optimum"]
    objectives = ", ".join(f"{k} {v:.4g}" for k, v in opt["objectives"].items())
    console.print(
        f"{result.generations} generations, {result.evaluations:,} evaluations in "
        f"{result.seconds:.1f} s; front {len(outcome.evaluation.X)} "
        f"({outcome.summary['front']['rejected_by_recheck']} rejected on the fine grid); "
        f"optimum row {outcome.index}: {objectives} -> {out}"
    )
