"""How long must the proof pull's hold be? Each trajectory's verdict and held pull at
``platform.protocol.proof_hold`` (the params', 0.5 s) against shorter holds, with the wall time
per run (docs/decisions/0045).

The trajectories are those the search lives on: the polished front of a finished run
(``data/polish/optimize/front.parquet``), and the first ``n`` sampled trajectories
(``data/trajectories.parquet``), so run it in a checkout whose `dvc repro` has finished.

Run: python bench/proof_hold.py [n_sampled] [HOLD,HOLD,...] [n_front] [workers]
     (default 60, 0.3,0.2, the whole front, 2)
"""

from __future__ import annotations

import sys
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.data.acquisition import sampled_specs
from ftfof.pipeline.bench import bench, context_of
from ftfof.pipeline.catalog import path
from ftfof.pipeline.params_file import load_params
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec
from ftfof.trajectory.bezier import DECISION_NAMES


def with_hold(spec: SampleSpec, hold: float) -> SampleSpec:
    protocol = spec.platform.protocol.model_copy(update={"proof_hold": hold})
    return replace(spec, platform=spec.platform.model_copy(update={"protocol": protocol}))


def verdict(job: tuple[SampleSpec, float]) -> tuple[str, float, float, float, float]:
    """(key, hold, proof_held, held_pull, wall seconds) of one run."""
    spec, hold = job
    r = simulate(with_hold(spec, hold))
    return spec.key, hold, r.scalars["proof_held"], round(r.scalars["held_pull"], 4), r.wall_time


def main(n: int, holds: list[float], n_front: int | None, workers: int) -> None:
    params = load_params(Path("params.yaml"))
    on = bench(params, context_of(params))
    front = pq.read_table(path("polish_optimize") / "front.parquet").to_pandas()[:n_front]
    specs = [on.bezier("front", i, x) for i, x in enumerate(front[list(DECISION_NAMES)].values)]
    sampled, _ = sampled_specs(on, pq.read_table(path("trajectories")), params.robot, "x", n)
    specs += sampled[:n]
    default = params.platform.protocol.proof_hold
    jobs = [(s, h) for s in specs for h in [default, *holds]]
    with ProcessPoolExecutor(workers) as pool:
        runs: dict[str, dict[float, tuple]] = {}
        for key, hold, held, pull, wall in pool.map(verdict, jobs):
            runs.setdefault(key, {})[hold] = (held, pull, wall)
    base_wall = np.mean([r[default][2] for r in runs.values()])
    holders = sum(r[default][0] == 1.0 for r in runs.values())
    print(f"{len(runs)} trajectories ({len(runs) - n} polished, {n} sampled); {holders} hold")
    for hold in holds:
        differ = [k for k, r in runs.items() if r[hold][:2] != r[default][:2]]
        wall = np.mean([r[hold][2] for r in runs.values()])
        print(
            f"hold {hold} s: {len(runs) - len(differ)} of {len(runs)} the same verdict and held "
            f"pull; wall per run {wall / base_wall - 1:+.0%}; differ: {', '.join(differ[:12])}"
        )


if __name__ == "__main__":
    args = sys.argv[1:]
    main(
        int(args[0]) if args else 60,
        [float(h) for h in args[1].split(",")] if len(args) > 1 else [0.3, 0.2],
        int(args[2]) if len(args) > 2 else None,
        int(args[3]) if len(args) > 3 else 2,
    )
