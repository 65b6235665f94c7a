"""`ftfof study eps`: the ε-Bezier baseline re-timed at each ε, simulated on the selected robot's
platform in a process pool, measured (:mod:`ftfof.study.eps`), written as JSON and a figure."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ftfof.config import Params
from ftfof.errors import ParamsError
from ftfof.files import save_figure, write_json
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.report.eps_study import eps_figure
from ftfof.study.eps import EpsPoint, EpsStudy, simulate


def parse_epsilons(text: str) -> list[float]:
    """``0,0.5,1`` -> distinct, finite, non-negative values in increasing order."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise ParamsError("--epsilons", f"{text!r} is not comma-separated numbers") from None
    if not all(np.isfinite(v) and v >= 0 for v in values) or len(set(values)) != len(values):
        raise ParamsError("--epsilons", f"need distinct, finite values >= 0 (got {text})")
    return sorted(values)


def run(
    params: Params, epsilons: Sequence[float], out: Path, figure: Path, workers: int
) -> list[EpsPoint]:
    """Simulate every ε (:func:`study_of`), then write the report to ``out`` and the figure to
    ``figure``: a failed simulation writes nothing."""
    study = study_of(params, epsilons, workers)
    save_figure(eps_figure(study), figure)
    write_json(out, study.report())
    return study.points


def study_of(params: Params, epsilons: Sequence[float], workers: int) -> EpsStudy:
    """The ε study of the selected robot's ε-Bezier baseline on its platform."""
    ctx = context_of(params)
    base = baseline_trajectories(params, ctx)["eps_bezier"]
    return simulate(bench(params, ctx), base, epsilons, workers)
