"""NSGA-II on the trained surrogates vs pymoo's own floor (issue 6 goals: ratio <= 1.5; the
batched evaluation >= 20x faster than evaluating the population one individual at a time).

The floor is the same NSGA-II (population, operators, seed, initial population, problem shape)
on a problem whose objectives and constraints are fixed random linear maps: microseconds per
population, so what remains is pymoo's own cost per generation.

Run: python bench/bench_optimize.py [generations]   (default: params.yaml, the paper's 2000)
Needs the trained models in data/models (`dvc repro train`).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from pymoo.core.problem import Problem

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import best_of, row
from ftfof.optimize.search import search
from ftfof.pipeline import catalog
from ftfof.pipeline.optimize import prepare
from ftfof.pipeline.params_file import load_params
from stages.runtime import tune_allocator


class ZeroCostProblem(Problem):
    """The template's shape and box; F and G are fixed random linear maps of x."""

    def __init__(self, template: Problem, seed: int = 0):
        rng = np.random.default_rng(seed)
        lower, upper = np.asarray(template.xl), np.asarray(template.xu)
        self.centre, self.span = (upper + lower) / 2, upper - lower
        self.to_F = rng.standard_normal((template.n_var, template.n_obj))
        # scaled so that most of the box is feasible, as in the seeded trajectory search
        self.to_G = rng.standard_normal((template.n_var, template.n_ieq_constr)) / template.n_var
        super().__init__(
            n_var=template.n_var,
            n_obj=template.n_obj,
            n_ieq_constr=template.n_ieq_constr,
            xl=lower,
            xu=upper,
        )

    def _evaluate(self, x, out, *args, **kwargs) -> None:
        unit = (x - self.centre) / self.span
        out["F"] = unit @ self.to_F
        out["G"] = unit @ self.to_G - 0.25


class TimedProblem(Problem):
    """The real problem, with the time spent in its evaluation summed."""

    def __init__(self, inner: Problem):
        self.inner, self.seconds = inner, 0.0
        super().__init__(
            n_var=inner.n_var,
            n_obj=inner.n_obj,
            n_ieq_constr=inner.n_ieq_constr,
            xl=inner.xl,
            xu=inner.xu,
        )

    def _evaluate(self, x, out, *args, **kwargs) -> None:
        started = time.perf_counter()
        self.inner._evaluate(x, out, *args, **kwargs)
        self.seconds += time.perf_counter() - started


def main(generations: int | None) -> None:
    tune_allocator()  # as in every `ftfof` process
    root = Path(__file__).resolve().parents[1]
    params = load_params(root / "params.yaml")
    setup = prepare(params, root / catalog.path("models"))
    settings = setup.settings
    if generations is not None:
        from dataclasses import replace

        settings = replace(settings, generations=generations)
    problem, initial = setup.problem, setup.initial

    batched = best_of(lambda: problem.evaluate_population(initial), repeats=10)
    single = best_of(
        lambda: [problem.evaluate_population(initial[i : i + 1]) for i in range(len(initial))],
        repeats=2,
    )
    floor = search(ZeroCostProblem(problem), settings, initial)
    timed = TimedProblem(problem)
    real = search(timed, settings, initial)
    n = settings.generations
    print(
        f"{setup.ctx.name}: population {settings.population}, {n} generations, "
        f"{problem.n_var} variables, {problem.n_obj} objectives, {problem.n_ieq_constr} constraints"
    )
    print(row("evaluate one individual at a time (baseline)", single))
    print(row("evaluate the population in one batch", batched, single))
    print(row("NSGA-II, zero-cost problem: per generation", floor.seconds / n))
    print(row("NSGA-II on the surrogates: per generation", real.seconds / n))
    print(row("  of which evaluating the offspring", timed.seconds / n))
    pymoo_share = (real.seconds - timed.seconds) / n
    print(row("  of which pymoo (sorting, crowding, operators)", pymoo_share))
    print(f"total: floor {floor.seconds:.1f} s, surrogates {real.seconds:.1f} s")
    print(f"ratio to pymoo's floor: {real.seconds / floor.seconds:.2f} (goal <= 1.5)")
    feasible = [r.history[-1].feasible for r in (floor, real)]
    print(f"feasible in the last population: floor {feasible[0]}, surrogates {feasible[1]}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else None)
