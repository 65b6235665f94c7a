"""Stage `evaluate`: re-simulate the optimum, front members and baselines on the platform; write
the report, gathering the climb, slip and study stages' outputs beside its own.

The simulations are a resumable job under ``data/evaluate/`` (:mod:`ftfof.pipeline.evaluate`);
the Table I analogue and the platform's figures come from them (:mod:`ftfof.evaluate.run`). The
robot's stages are read from their catalog places beside ``--metrics`` and ``--out``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import REPORTS, path
from stages.common import ParamsOption, WorkersOption, console, stage

OPTIMIZE = path("polish_optimize")
MODELS = path("refine_models")
REFINE = path("refine_report")
OUT = path("evaluate")
REPORT = path("report")
METRICS = path("metrics")
EXPORT = path("export")
FIGURES = REPORTS  # the PNGs the earlier stages wrote


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    optimize: Annotated[Path, typer.Option(help="Optimum and front (polish's).")] = OPTIMIZE,
    models: Annotated[Path, typer.Option(help="The surrogates it was found on.")] = MODELS,
    figures: Annotated[Path, typer.Option(help="Where the stages' PNGs are.")] = FIGURES,
    refine: Annotated[Path, typer.Option(help="The refinement report (JSON).")] = REFINE,
    out: Annotated[Path, typer.Option(help="Simulations of this evaluation.")] = OUT,
    report: Annotated[Path, typer.Option(help="Self-contained HTML report.")] = REPORT,
    metrics: Annotated[Path, typer.Option(help="Metrics JSON.")] = METRICS,
    export: Annotated[Path, typer.Option(help="Controller CSV of the optimum.")] = EXPORT,
    workers: Annotated[int | None, WorkersOption] = None,
) -> None:
    """Re-simulate the optimum against the common trajectories; report, metrics, export."""
    from ftfof.evaluate.runs import OPTIMUM
    from ftfof.pipeline.evaluate import Paths, Robot, run
    from ftfof.pipeline.params_file import load_params

    params = load_params(params_path)
    robot = Robot.at(metrics.parent, out.parent)  # the climb, slip and study stages' outputs
    paths = Paths(optimize, models, figures, out, report, metrics, export, refine, robot)
    summary = run(params, paths, workers).summary
    opt = summary["table"][OPTIMUM]
    console.print(
        f"optimum vs {summary['reference']}: pull {opt['peak_pull_change']:+.1f} %, "
        f"detachment jitter {opt['jitter_change']:+.1f} %, landing pre-pressure "
        f"{opt['landing_pre_pressure_change']:+.1f} %, film {1e3 * opt['min_bend_radius']:.2f} mm "
        f"-> {report}"
    )
