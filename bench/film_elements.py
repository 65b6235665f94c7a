"""Table I against the film's elements: every baseline and the published optimum on each film, as
a change against the acquisition's uniform film (today's) and against the converged reference
(uniform, evaluate's check_nodes), with the CPU time each costs. Shows which films keep Table I
(pull, landing, jitter within 1 %, film radius within 5 %) and at what speed.

A film is ``N`` (uniform, N elements) or ``N@h`` (graded: N elements, h mm long over the grip and
at the clamp edge, growing to the pad's end; docs/simulator.md, "Graded film elements"). The runs
are interleaved film by film within each trajectory, in this one process, so that other load on
the machine falls on every film alike; the time is each run's CPU seconds, the least of
``rounds`` runs.

Run: python bench/film_elements.py [FILM,FILM,...] [rounds]   (default 20,30,40,50,80 and 1)
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import least_cpu
from ftfof.evaluate.runs import PAPER_OPTIMUM, figures_of
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import load_params
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec, baseline_specs
from stages.runtime import tune_allocator

FIGURES = ("peak_pull", "landing_pre_pressure", "jitter", "min_bend_radius")
SHORT = {
    "peak_pull": "pull",
    "landing_pre_pressure": "land",
    "jitter": "jit",
    "min_bend_radius": "R",
}
TOLERANCE = {"peak_pull": 1.0, "landing_pre_pressure": 1.0, "jitter": 1.0, "min_bend_radius": 5.0}


def parse_film(label: str) -> tuple[int, float | None]:
    """``N`` -> (N, None), uniform; ``N@h`` -> (N, h mm in m), graded."""
    count, _, edge = label.partition("@")
    return int(count), float(edge) / 1000 if edge else None


def film_settings(label: str) -> dict[str, int | float | None]:
    """The solver settings of the film ``label`` (``nodes`` and ``edge_element``)."""
    nodes, edge = parse_film(label)
    return {"nodes": nodes, "edge_element": edge}


def on_film(spec: SampleSpec, label: str) -> SampleSpec:
    """``spec`` simulated on the film ``label``."""
    solver = spec.solver.model_copy(update=film_settings(label))
    return dataclasses.replace(spec, key=f"{spec.key}:{label}", solver=solver)


def run_all(specs: list[SampleSpec], films: list[str], rounds: int, T3: float) -> pd.DataFrame:
    """One row per (trajectory, film): Table I's figures and the least CPU seconds a run."""
    rows = []
    for spec in specs:
        for label in films:
            seconds, runs = least_cpu(lambda s=spec, f=label: simulate(on_film(s, f)), rounds)
            assert all(r.ok for r in runs), runs[0].error
            result = runs[-1]
            figures = figures_of(pd.Series({**result.scalars, **result.channels}), T3)
            name = spec.source.removeprefix("baseline:")
            rows.append({"name": name, "film": label, **figures, "seconds": seconds})
    return pd.DataFrame(rows).set_index(["name", "film"])


def changes(table: pd.DataFrame, against: str) -> pd.DataFrame:
    """Each figure's change (%) against the film ``against``, the same trajectory's."""
    base = table.xs(against, level="film")
    out = 100 * (table[list(FIGURES)] / base[list(FIGURES)].reindex(table.index, level="name") - 1)
    return out.rename(columns=SHORT)


def summary(table: pd.DataFrame, today: str, converged: str) -> pd.DataFrame:
    """Per film, the largest |change| over the four baselines and Pf's own, against today's film
    and the converged one, and the time as a ratio to today's film (range over trajectories)."""
    ratio = table["seconds"] / table["seconds"].xs(today, level="film").reindex(
        table.index, level="name"
    )
    parts = []
    for against in (today, converged):
        c = changes(table, against).abs()
        pf = c.index.get_level_values("name") == PAPER_OPTIMUM.removeprefix("baseline:")
        four = c[~pf].groupby(level="film").max().add_suffix(f" 4 vs {against}")
        parts += [four, c[pf].droplevel("name").add_suffix(f" Pf vs {against}")]
    time_range = ratio.groupby(level="film").agg(["min", "max"]).add_prefix("time ")
    return pd.concat([*parts, time_range], axis=1)


def main(films: list[str], rounds: int) -> None:
    tune_allocator()
    params = load_params(Path(__file__).resolve().parents[1] / "params.yaml")
    ctx = context_of(params)
    on = bench(params, ctx)
    specs = baseline_specs(on, baseline_trajectories(params, ctx))
    if ctx.robot.published_optimum is not None:
        specs.append(on.bezier(PAPER_OPTIMUM, 0, np.asarray(ctx.robot.published_optimum)))
    today = str(params.acquire.solver.nodes)
    converged = str(params.evaluate.check_nodes or 2 * params.acquire.solver.nodes)
    films = list(dict.fromkeys([today, converged, *films]))
    table = run_all(specs, films, rounds, ctx.policy.timing.T3)
    pd.set_option("display.width", 250, "display.max_columns", 40, "display.precision", 3)
    print("figures and CPU seconds a run\n", table, "\n")
    print(f"change (%) against uniform {today}\n", changes(table, today), "\n")
    print(f"change (%) against uniform {converged}\n", changes(table, converged), "\n")
    print(f"largest |change| (%), tolerance {TOLERANCE}\n", summary(table, today, converged).T)


if __name__ == "__main__":
    default = "20,30,40,50,80"
    main(
        (sys.argv[1] if len(sys.argv) > 1 else default).split(","),
        int(sys.argv[2]) if len(sys.argv) > 2 else 1,
    )
