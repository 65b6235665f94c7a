"""`ftfof study eps`: the ε-Bezier baseline re-timed at each ε, simulated on the selected robot's
platform in a process pool, measured (:mod:`ftfof.study.eps`), written as JSON and a figure."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ftfof.config import Params
from ftfof.errors import ParamsError, SimulationError
from ftfof.files import save_figure, write_json
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.report.eps_study import eps_figure
from ftfof.sim.pool import run_all
from ftfof.study.eps import EpsPoint, measure, report, swept


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
    """Simulate every ε, write the report to ``out`` and the figure to ``figure``; a failed
    simulation is an error naming its ε, and then nothing is written."""
    ctx = context_of(params)
    on = bench(params, ctx)
    base = baseline_trajectories(params, ctx)["eps_bezier"]
    specs = [
        on.analytic(f"eps:{e:g}", i, trajectory)
        for i, (e, trajectory) in enumerate(zip(epsilons, swept(base, epsilons), strict=True))
    ]
    results = run_all(specs, workers)
    T3 = ctx.policy.timing.T3
    points: list[EpsPoint] = []
    landings = {}
    for e, r in zip(epsilons, results, strict=True):
        if not r.ok:
            raise SimulationError(f"eps_bezier at ε = {e:g}", r.error)
        points.append(measure(e, r.channels, r.scalars, T3))
        landed = r.channels["switch"] > 0
        landings[e] = (r.channels["t"][landed], r.channels["Fp"][landed])
    press = specs[0].pre_pressure
    save_figure(eps_figure(points, landings, press), figure)
    write_json(out, report(points, press))
    return points
