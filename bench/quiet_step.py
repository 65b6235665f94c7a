"""The quiet-flight step (``acquire.solver.quiet_step``, docs/simulator.md, "A longer step in
quiet flight"): Table I's five runs and ``n`` sampled trajectories (bench_acquire's), each at
every quiet step given, interleaved run by run in this one process; CPU seconds (the least of
``rounds``) and each figure's change against one step throughout. Two runs of every setting are
compared bit for bit when ``rounds`` >= 2.

Run: python bench/quiet_step.py [n_samples] [QUIET,QUIET,...] [rounds]   (default 24, 1e-3,2e-3, 2)
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.evaluate.runs import PAPER_OPTIMUM, figures_of
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import load_params
from ftfof.seeds import seed_for
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec
from ftfof.trajectory.sampling import sample_feasible
from stages.runtime import tune_allocator

FIGURES = (
    "peak_pull",
    "landing_pre_pressure",
    "jitter",
    "min_bend_radius",
    "peak_body_acc",
    "max_clearance",
)


def with_quiet(spec: SampleSpec, quiet: float | None) -> SampleSpec:
    return dataclasses.replace(spec, solver=spec.solver.model_copy(update={"quiet_step": quiet}))


def main(n: int, quiets: list[float], rounds: int) -> None:
    tune_allocator()
    params = load_params(Path(__file__).resolve().parents[1] / "params.yaml")
    ctx = context_of(params)
    on = bench(params, ctx)
    specs = baseline_specs(on, baseline_trajectories(params, ctx))
    specs.append(on.bezier(PAPER_OPTIMUM, 0, np.asarray(ctx.robot.published_optimum)))
    X = sample_feasible(ctx.policy, n, seed=seed_for(params.base.seed, "bench")).X
    specs += [on.bezier("sampled", i, x) for i, x in enumerate(X)]
    T3 = ctx.policy.timing.T3
    simulate(specs[0])  # warm-up
    rows, repeats = [], 0
    for spec in specs:
        for quiet in [None, *quiets]:
            seconds, runs = [], []
            for _ in range(rounds):
                start = time.process_time()
                runs.append(simulate(with_quiet(spec, quiet)))
                seconds.append(time.process_time() - start)
            result = runs[0]
            assert result.ok, result.error
            repeats += all(
                all(np.array_equal(r.channels[k], result.channels[k]) for k in result.channels)
                for r in runs[1:]
            )
            figures = figures_of(pd.Series({**result.scalars, **result.channels}), T3)
            rows.append(
                {
                    "run": spec.source.removeprefix("baseline:") + f" {spec.sample_id}",
                    "table": spec.source.startswith("baseline:"),
                    "quiet": quiet or 0.0,
                    **{f: figures.get(f, result.scalars.get(f)) for f in FIGURES},
                    "quiet_steps": result.scalars["quiet_steps"],
                    "steps": result.scalars["steps"],
                    "seconds": min(seconds),
                }
            )
    table = pd.DataFrame(rows).set_index(["run", "quiet"])
    base = table.xs(0.0, level="quiet")
    pd.set_option("display.width", 250, "display.max_columns", 40, "display.precision", 4)
    print("Table I's runs\n", table[table.table].drop(columns="table"), "\n")
    for quiet in quiets:
        at = table.xs(quiet, level="quiet")
        change = 100 * (at[list(FIGURES)] / base[list(FIGURES)] - 1)
        ratio = at.seconds / base.seconds
        for label, rows_of in (("Table I", at.table), (f"{n} sampled", ~at.table)):
            c, r = change[rows_of].abs(), ratio[rows_of]
            total = at.seconds[rows_of].sum() / base.seconds[rows_of].sum()
            print(
                f"quiet_step {quiet * 1e3:g} ms, {label}: CPU {r.median():.3f}x median "
                f"({r.min():.2f}-{r.max():.2f}), {total:.3f}x "
                f"in all; quiet steps {at.quiet_steps[rows_of].mean():.0f} of "
                f"{at.steps[rows_of].mean():.0f}"
            )
            print("   largest |change| %:", c.max().round(4).to_dict())
    if rounds > 1:
        print(f"bit-identical between runs: {repeats} of {len(specs) * (len(quiets) + 1)}")


if __name__ == "__main__":
    main(
        int(sys.argv[1]) if len(sys.argv) > 1 else 24,
        [float(q) for q in (sys.argv[2] if len(sys.argv) > 2 else "1e-3,2e-3").split(",")],
        int(sys.argv[3]) if len(sys.argv) > 3 else 2,
    )
