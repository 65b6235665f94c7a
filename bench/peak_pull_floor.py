"""Where the peak pull comes from, and how low a trajectory could take it (docs/simulator.md).

On the calibrated platform the peak pull of every trajectory is the peel's initiation: the foot
has lifted about 1 mm, every bond is still intact, and the heel's bonds are opened at a rate that
the bond law's rate factor R(v) = 1 + (v / v*)^n multiplies. This script prints, for the
polynomial baseline and the paper's optimum Pf:

1. when the peak comes, how many bonds hold then, and the pull later in the peel;
2. the peak with the rate factor switched off (v* -> infinity): the quasi-static floor;
3. the polynomial's peak when the same path runs 2, 4 and 8 times slower (every T scaled), the
   only way left to open the heel more slowly.

Run: python bench/peak_pull_floor.py   (about 10 s on one core)
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.config.validate import parse_params
from ftfof.data import targets
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import read_yaml
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec, baseline_specs

SLOWDOWNS = (1, 2, 4, 8)
BROKEN = (0.25, 0.5, 0.75)


def params_slowed(raw: dict, factor: float):
    robot_name = raw["robot"]
    robot = dict(raw["robots"][robot_name])
    robot["timing"] = {k: v * factor for k, v in robot["timing"].items()}
    solver = {**raw["acquire"]["solver"], "time_budget": 60.0 * factor}
    slowed = {
        **raw,
        "robots": {**raw["robots"], robot_name: robot},
        "acquire": {**raw["acquire"], "solver": solver},
    }
    return parse_params(slowed, f"params.yaml with every T x {factor}")


def describe(spec: SampleSpec, T3: float) -> str:
    result = simulate(spec)
    c = result.channels
    t, bonds = c["t"], c["bonds"]
    pull = targets.full_rate(c, T3)["pull"]
    peak = int(np.argmax(pull))
    start = bonds[np.flatnonzero(t >= 0)[0]]
    later = []
    for share in BROKEN:
        at = np.flatnonzero((t >= 0) & (bonds <= start * (1 - share)))
        if at.size:
            later.append(f"{pull[at[0]]:.2f} N at {100 * share:.0f} % broken")
    return (
        f"peak {pull[peak]:.2f} N at t = {t[peak]:.3f} s, foot {1e3 * c['z_foot'][peak]:.2f} mm "
        f"up, {bonds[peak]:.0f} of {start:.0f} bonds holding; then {', '.join(later)}"
    )


def main() -> None:
    raw = read_yaml(Path(__file__).resolve().parents[1] / "params.yaml")
    params = params_slowed(raw, 1.0)
    ctx = context_of(params)
    on = bench(params, ctx)
    T3 = ctx.policy.timing.T3
    specs = baseline_specs(on, baseline_trajectories(params, ctx), ["polynomial"])
    if ctx.robot.published_optimum is not None:
        specs.append(on.bezier("paper_optimum", 0, np.array(ctx.robot.published_optimum)))
    print("1. the peak pull")
    for spec in specs:
        print(f"   {spec.source:<22} {describe(spec, T3)}")
    print("2. without the rate factor (v* -> infinity)")
    for spec in specs:
        quasi_static = replace(spec, surface=spec.surface.model_copy(update={"rate_speed": 1e9}))
        print(f"   {spec.source:<22} peak {simulate(quasi_static).scalars['peak_pull']:.2f} N")
    print("3. the polynomial's path run slower")
    for factor in SLOWDOWNS:
        slowed = params_slowed(raw, factor)
        slow_ctx = context_of(slowed)
        spec = baseline_specs(
            bench(slowed, slow_ctx), baseline_trajectories(slowed, slow_ctx), ["polynomial"]
        )[0]
        peak = simulate(spec).scalars["peak_pull"]
        print(f"   every T x {factor}: T1 = {slow_ctx.policy.timing.T1:.2f} s, peak {peak:.2f} N")


if __name__ == "__main__":
    main()
