"""Longer steps in the protocol's phases (``acquire.solver.phase_steps``, docs/simulator.md, "A
longer step outside the peel and the landing"): Table I's five runs and ``n`` sampled
trajectories (bench_acquire's), each at every schedule given, interleaved run by run in this one
process; CPU seconds (the least of ``rounds``) and each Table I figure's change against one step
throughout. Two runs of every schedule are compared bit for bit when ``rounds`` >= 2.

A schedule is ``all``, ``all-a-b`` (all but phases a and b) or ``a+b=H+...`` (config's
``LongPhase`` names: settle, press, press_hold, flight, landing_hold; a phase without ``=H`` takes
``long``).

Run: python bench/long_step.py [n_samples] [SCHEDULE,SCHEDULE,...] [rounds] [long]
     (default 24, all, 2, 2e-3)
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.against_revision import specs_of
from bench.common import least_cpu
from ftfof.config.stages import LONG_PHASES
from ftfof.evaluate.runs import figures_of
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec
from stages.runtime import tune_allocator

FIGURES = (
    "peak_detachment",
    "peak_pre_pressure",
    "peak_pull",
    "landing_pre_pressure",
    "jitter",
    "min_bend_radius",
    "peak_body_acc",
    "max_clearance",
)


def schedule_of(name: str, long: float) -> dict[str, float]:
    """``all``, ``all-a-b`` or ``a+b=H`` as a phase -> step schedule."""
    if name == "all" or name.startswith("all-"):
        drop = set(name.split("-")[1:])
        return {p: long for p in LONG_PHASES if p not in drop}
    items = [item.partition("=") for item in name.split("+")]
    schedule = {p: float(h) if h else long for p, _, h in items}
    assert set(schedule) <= set(LONG_PHASES), name
    return schedule


def with_schedule(spec: SampleSpec, schedule: dict[str, float]) -> SampleSpec:
    update = {"phase_steps": schedule}
    return dataclasses.replace(spec, solver=spec.solver.model_copy(update=update))


def main(n: int, sets: list[str], rounds: int, long: float) -> None:
    tune_allocator()
    specs, T3 = specs_of(n)
    simulate(specs[0])  # warm-up
    settings = [("today", {}), *((s, schedule_of(s, long)) for s in sets)]
    rows, repeats = [], 0
    for spec in specs:
        for label, schedule in settings:
            seconds, runs = least_cpu(
                lambda s=spec, h=schedule: simulate(with_schedule(s, h)), rounds
            )
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
                    "set": label,
                    **{f: figures.get(f, result.scalars.get(f)) for f in FIGURES},
                    "long_steps": result.scalars["long_steps"],
                    "steps": result.scalars["steps"],
                    "seconds": seconds,
                }
            )
        print(".", end="", flush=True)
    print()
    table = pd.DataFrame(rows).set_index(["run", "set"])
    base = table.xs("today", level="set")
    pd.set_option("display.width", 250, "display.max_columns", 40, "display.precision", 5)
    print("Table I's runs\n", table[table.table].drop(columns="table"), "\n")
    for label, _ in settings[1:]:
        at = table.xs(label, level="set")
        change = 100 * (at[list(FIGURES)] / base[list(FIGURES)] - 1)
        ratio = at.seconds / base.seconds
        print(f"== {label} (long {long * 1e3:g} ms): change % against today (Table I)")
        print(change[at.table].assign(time=ratio[at.table]).round(4))
        for name, rows_of in (("Table I", at.table), (f"{n} sampled", ~at.table)):
            if not rows_of.any():
                continue
            c, r = change[rows_of], ratio[rows_of]
            total = at.seconds[rows_of].sum() / base.seconds[rows_of].sum()
            print(
                f"{label}, {name}: CPU {r.median():.3f}x median ({r.min():.2f}-{r.max():.2f}), "
                f"{total:.3f}x in all; long steps {at.long_steps[rows_of].mean():.0f} of "
                f"{at.steps[rows_of].mean():.0f} (today {base.steps[rows_of].mean():.0f})"
            )
            print("   change % min:", c.min().round(4).to_dict())
            print("   change % max:", c.max().round(4).to_dict())
        far = change[(change.abs() > 1).any(axis=1)]
        if len(far):
            print("   runs with a figure more than 1 % off:\n", far.round(3))
    if rounds > 1:
        print(f"bit-identical between runs: {repeats} of {len(specs) * len(settings)}")


if __name__ == "__main__":
    main(
        int(sys.argv[1]) if len(sys.argv) > 1 else 24,
        (sys.argv[2] if len(sys.argv) > 2 else "all").split(","),
        int(sys.argv[3]) if len(sys.argv) > 3 else 2,
        float(sys.argv[4]) if len(sys.argv) > 4 else 2e-3,
    )
