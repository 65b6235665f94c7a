"""A simulator change against a git revision's simulator (default HEAD), in one process: Table I's
five runs and ``n`` sampled trajectories (bench_acquire's), each simulated by both, interleaved
run by run so that other load falls on both alike. Prints every Table I and proof-pull figure's
change (%) against the revision, whether each pull held alike, and the CPU time ratio (the
least of ``rounds`` runs).

It measures the physics-preserving levers of issue 54: a change passes where every Table I
figure stays within 1 % and the film radius within 5 % (docs/simulator.md, "On the plate foot").

Run: python bench/against_revision.py [n_samples] [revision] [rounds]   (default 24, HEAD, 1)
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import least_cpu
from bench.reference import reference_simulate
from ftfof.evaluate.runs import PAPER_OPTIMUM, figures_of
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import load_params
from ftfof.seeds import seed_for
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec, baseline_specs
from ftfof.trajectory.sampling import sample_feasible
from stages.runtime import tune_allocator

FIGURES = (
    "peak_pull",
    "landing_pre_pressure",
    "jitter",
    "min_bend_radius",
    "rebond_fraction",
    "held_pull",
)
TOLERANCE = {"min_bend_radius": 5.0}  # %, every other figure 1 %


def specs_of(n: int) -> tuple[list[SampleSpec], float]:
    """Table I's five runs and ``n`` sampled ones, and T3."""
    params = load_params(Path(__file__).resolve().parents[1] / "params.yaml")
    ctx = context_of(params)
    on = bench(params, ctx)
    specs = baseline_specs(on, baseline_trajectories(params, ctx))
    specs.append(on.bezier(PAPER_OPTIMUM, 0, np.asarray(ctx.robot.published_optimum)))
    if n:
        X = sample_feasible(ctx.policy, n, seed=seed_for(params.base.seed, "bench")).X
        specs += [on.bezier("sampled", i, x) for i, x in enumerate(X)]
    return specs, ctx.policy.timing.T3


def row_of(spec: SampleSpec, result: Any, T3: float, seconds: float) -> dict[str, Any]:
    """One run's Table I and proof-pull figures; a failed run stops the bench, named."""
    if not result.ok:
        raise RuntimeError(f"{spec.key}: {result.error}")
    figures = figures_of(pd.Series({**result.scalars, **result.channels}), T3)
    return {
        "run": spec.source.removeprefix("baseline:") + f" {spec.sample_id}",
        "table": not spec.source.startswith("sampled"),
        **{f: figures.get(f, result.scalars.get(f)) for f in FIGURES},
        "held": result.scalars["proof_held"],
        "seconds": seconds,
    }


def main(n: int, revision: str, rounds: int) -> None:
    tune_allocator()
    before_simulate = reference_simulate(revision)
    specs, T3 = specs_of(n)
    simulate(specs[0])  # warm-up: imports, numba cache
    before_simulate(specs[0])
    before, after = [], []
    for spec in specs:
        seconds, results = least_cpu(lambda s=spec: before_simulate(s), rounds)
        before.append(row_of(spec, results[0], T3, seconds))
        seconds, results = least_cpu(lambda s=spec: simulate(s), rounds)
        after.append(row_of(spec, results[0], T3, seconds))
        print(".", end="", flush=True)
    print()
    old, new = pd.DataFrame(before).set_index("run"), pd.DataFrame(after).set_index("run")
    change = 100 * (new[list(FIGURES)] / old[list(FIGURES)] - 1)
    pd.set_option("display.width", 250, "display.max_columns", 40, "display.precision", 4)
    print(f"Table I's runs against {revision}: change %, and the time ratio")
    print(change[new.table].assign(time=(new.seconds / old.seconds)[new.table]).round(4))
    for name, rows in (("Table I", new.table), (f"{n} sampled", ~new.table)):
        c = change[rows].abs()
        total = new.seconds[rows].sum() / old.seconds[rows].sum()
        alike = (new.held == old.held) | (new.held.isna() & old.held.isna())
        print(
            f"{name}: CPU {total:.3f}x in all ({old.seconds[rows].mean():.3f} -> "
            f"{new.seconds[rows].mean():.3f} s a run); held alike in "
            f"{int(alike[rows].sum())} of {int(rows.sum())}"
        )
        print("   largest |change| %:", c.max().round(4).to_dict())
        over = c[(c > pd.Series({f: TOLERANCE.get(f, 1.0) for f in FIGURES})).any(axis=1)]
        if len(over):
            print("   runs past tolerance:\n", over.round(3))


if __name__ == "__main__":
    main(
        int(sys.argv[1]) if len(sys.argv) > 1 else 24,
        sys.argv[2] if len(sys.argv) > 2 else "HEAD",
        int(sys.argv[3]) if len(sys.argv) > 3 else 1,
    )
