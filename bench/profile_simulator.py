"""Where a platform simulation spends its time: Exudyn's own timers per category (the residual,
Jacobians, factorisation, the Python pre-step), its Newton statistics, and the wall time per
sample against the film's element count, in this process, at the acquisition's settings.

The solver is wrapped only to read its timers and iteration counters; the simulation is the
acquisition's. Results: docs/simulator.md, "Where the time goes".

Run: python bench/profile_simulator.py [n_samples]
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import exudyn as exu
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import ftfof.sim.simulate as sim
from ftfof.pipeline.bench import bench, context_of
from ftfof.pipeline.params_file import load_params
from ftfof.seeds import seed_for
from ftfof.trajectory.sampling import sample_feasible
from stages.runtime import tune_allocator

CATEGORIES = (
    "ODE2RHS",
    "python",
    "newtonIncrement",
    "totalJacobian",
    "reactionForces",
    "factorization",
    "AERHS",
    "writeSolution",
    "integrationFormula",
)
NODES = (10, 20, 40, 80)
SOLVER = exu.MainSolverImplicitSecondOrder


class Timed:
    """Exudyn's implicit solver, kept after the run so its timers and counters can be read."""

    last: SOLVER | None = None

    def __new__(cls):
        Timed.last = SOLVER()
        return Timed.last


def with_timers(spec):
    settings = SETTINGS(spec)
    settings.show.computationTime = True  # switches Exudyn's timers on; nothing is printed
    return settings


SETTINGS = sim._settings


def profile(specs) -> dict[str, float]:
    """Summed timer seconds per category, the total, and Newton counts over ``specs``."""
    sim.exu.MainSolverImplicitSecondOrder = Timed
    sim._settings = with_timers
    out: dict[str, float] = {}
    try:
        for spec in specs:
            result = sim.simulate(spec)
            assert result.ok, result.error
            timer, it = Timed.last.timer, Timed.last.it
            for name in (*CATEGORIES, "total"):
                out[name] = out.get(name, 0.0) + getattr(timer, name)
            for name in ("numberOfSteps", "newtonStepsCount", "newtonJacobiCount"):
                out[name] = out.get(name, 0.0) + getattr(it, name)
            out["wall"] = out.get("wall", 0.0) + result.wall_time
    finally:
        sim.exu.MainSolverImplicitSecondOrder = SOLVER
        sim._settings = SETTINGS
    return out


def main(n: int) -> None:
    tune_allocator()
    root = Path(__file__).resolve().parents[1]
    params = load_params(root / "params.yaml")
    ctx = context_of(params)
    on = bench(params, ctx)
    X = sample_feasible(ctx.policy, n + 1, seed=seed_for(params.base.seed, "bench")).X
    specs = [on.bezier("sampled", i, x) for i, x in enumerate(X)]
    sim.simulate(specs[0])  # warm-up: imports, numba cache
    specs = specs[1:]
    p = profile(specs)
    print(f"{n} samples at N = {params.acquire.solver.nodes}, one core")
    print(f"  wall {p['wall'] / n:.3f} s per sample; solver {p['total'] / n:.3f} s")
    for name in CATEGORIES:
        print(f"  {name:20s} {100 * p[name] / p['total']:5.1f} %")
    steps = p["numberOfSteps"]
    print(
        f"  Newton: {p['newtonStepsCount'] / steps:.2f} iterations per step, "
        f"{p['newtonJacobiCount'] / n:.0f} Jacobians per sample, {steps / n:.0f} steps"
    )
    print("film elements: seconds per sample (ratio to the acquisition's N)")
    walls = {}
    for nodes in NODES:
        solver = params.acquire.solver.model_copy(update={"nodes": nodes})
        runs = [sim.simulate(dataclasses.replace(s, solver=solver)) for s in specs]
        walls[nodes] = float(np.mean([r.wall_time for r in runs]))
    base = walls[params.acquire.solver.nodes]
    for nodes, wall in walls.items():
        print(f"  N = {nodes:3d}: {wall:.3f} s ({wall / base:.2f})")
    slope = np.polyfit(list(walls), list(walls.values()), 1)
    print(f"  {1e3 * slope[0]:.2f} ms per element, {slope[1]:.3f} s at N = 0")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 6)
