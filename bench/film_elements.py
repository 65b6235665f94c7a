"""Table I against the film's element count: every baseline and the published optimum at each N,
as a change against the acquisition's N (same process, two workers). Shows which N keep Table I
(pull, landing, jitter within 1 %, film radius within 5 %) and the time each costs.

Run: python bench/film_elements.py [N,N,...]   (default 20,30,40,50)
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.evaluate.runs import PAPER_OPTIMUM, figures_of
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import load_params
from ftfof.sim import pool
from stages.runtime import tune_allocator

FIGURES = ("peak_pull", "landing_pre_pressure", "jitter", "peak_body_acc", "min_bend_radius")


def main(counts: list[int]) -> None:
    tune_allocator()
    params = load_params(Path(__file__).resolve().parents[1] / "params.yaml")
    ctx = context_of(params)
    on = bench(params, ctx)
    specs = baseline_specs(on, baseline_trajectories(params, ctx))
    if ctx.robot.published_optimum is not None:
        specs.append(on.bezier(PAPER_OPTIMUM, 0, np.asarray(ctx.robot.published_optimum)))
    reference = params.acquire.solver.nodes
    counts = sorted({*counts, reference})
    T3 = ctx.policy.timing.T3
    rows: dict[tuple[str, int], dict[str, float]] = {}
    for n in counts:
        solver = params.acquire.solver.model_copy(update={"nodes": n})
        at_n = [dataclasses.replace(s, key=f"{s.key}:{n}", solver=solver) for s in specs]
        for result in (r for batch in pool.run_local(at_n, 2) for r in batch):
            assert result.ok, result.error
            figures = figures_of(pd.Series({**result.scalars, **result.channels}), T3)
            name = result.source.removeprefix("baseline:")
            rows[name, n] = {**{f: figures[f] for f in FIGURES}, "seconds": result.wall_time}
    print(f"change against N = {reference} (grip / element length integral where N % 10 == 0)")
    for name in dict.fromkeys(s.source.removeprefix("baseline:") for s in specs):
        for n in counts:
            here, base = rows[name, n], rows[name, reference]
            changes = " ".join(f"{f} {100 * (here[f] / base[f] - 1):+6.2f} %" for f in FIGURES)
            print(f"{name:14s} N = {n:3d}  {changes}  {here['seconds']:.2f} s")


if __name__ == "__main__":
    default = "20,30,40,50"
    main([int(v) for v in (sys.argv[1] if len(sys.argv) > 1 else default).split(",")])
