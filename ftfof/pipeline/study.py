"""`ftfof study eps`: the ε-Bezier baseline re-timed at each ε, simulated on the selected robot's
platform in a process pool, measured (:mod:`ftfof.study.eps`), written as JSON and a figure."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ftfof.config import Params
from ftfof.files import save_figure
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.summaries import write_metrics
from ftfof.report.eps_study import eps_figure
from ftfof.study.eps import EpsPoint, EpsStudy, simulate


def run(
    params: Params, epsilons: Sequence[float], out: Path, figure: Path, workers: int
) -> list[EpsPoint]:
    """Simulate every ε (:func:`study_of`), then write the report to ``out`` and the figure to
    ``figure``: a failed simulation writes nothing."""
    study = study_of(params, epsilons, workers)
    save_figure(eps_figure(study), figure)
    write_metrics("study", out, study.report())
    return study.points


def study_of(params: Params, epsilons: Sequence[float], workers: int) -> EpsStudy:
    """The ε study of the selected robot's ε-Bezier baseline on its platform."""
    ctx = context_of(params)
    base = baseline_trajectories(params, ctx)["eps_bezier"]
    return simulate(bench(params, ctx), base, epsilons, workers)
