"""Acquisition speed (goals: <= 0.1 s per 1.5 s sample per core, issue 36; 2-worker efficiency
>= 85 %), against the same samples simulated by the reference revision's simulator
(:mod:`bench.reference`, interleaved sample by sample in this process, and compared channel by
channel), on a 20-element film and with every bond connector kept on (the baselines, in this
process); the last also shows how far switching off idle bonds moves the Table I figures (Newton
converges within its tolerance either way). One-core figures are CPU seconds, so that other load
on the machine does not count.

Run: python bench/bench_acquire.py [n_samples] [reference revision]
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.reference import REFERENCE, reference_simulate
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.params_file import load_params
from ftfof.seeds import seed_for
from ftfof.sim import pool
from ftfof.sim.film import film_limit
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import Bench
from ftfof.trajectory.sampling import sample_feasible
from stages.runtime import tune_allocator


def cpu_seconds(fn: Callable[[], Any]) -> tuple[float, Any]:
    """CPU time of one call on this core, and its result."""
    start = time.process_time()
    result = fn()
    return time.process_time() - start, result


def relative_change(value: float, base: float) -> float:
    """|value / base - 1|, infinite where a figure appears from 0 (a run that never detached)."""
    if base == 0.0:
        return 0.0 if value == 0.0 else float("inf")
    return abs(value / base - 1.0)


def main(n: int, revision: str) -> None:
    tune_allocator()
    reference = reference_simulate(revision)
    root = Path(__file__).resolve().parents[1]
    params = load_params(root / "params.yaml")
    ctx = context_of(params)
    bench = Bench(
        ctx.robot, params.selected_surface, params.platform, params.acquire, params.base.seed
    )
    X = sample_feasible(ctx.policy, n, seed=seed_for(params.base.seed, "bench")).X
    specs = [bench.bezier("sampled", i, x) for i, x in enumerate(X)]
    simulate(specs[0])  # warm-up: imports, numba cache
    reference(specs[0])
    one_core, one_core_reference, identical = [], [], 0
    idle, all_on, one_core_all_on = [], [], []
    for spec in specs:
        seconds, before = cpu_seconds(lambda s=spec: reference(s))
        one_core_reference.append(seconds)
        seconds, result = cpu_seconds(lambda s=spec: simulate(s))
        one_core.append(seconds)
        assert result.ok, result.error
        identical += all(np.array_equal(before.channels[k], v) for k, v in result.channels.items())
        idle.append(result.scalars)
        seconds, everything_on = cpu_seconds(lambda s=spec: simulate(s, idle_bonds=False))
        all_on.append(everything_on.scalars)
        one_core_all_on.append(seconds)
    coarse = Bench(
        ctx.robot,
        params.selected_surface,
        params.platform,
        params.acquire.model_copy(
            update={"solver": params.acquire.solver.model_copy(update={"nodes": 20})}
        ),
        params.base.seed,
    )
    baseline = []
    for i, x in enumerate(X):
        baseline.append(cpu_seconds(lambda i=i, x=x: simulate(coarse.bezier("sampled", i, x)))[0])
    sim_seconds = specs[0].end_time
    per_sample = float(np.median(one_core))
    rates = {}
    for workers in (1, 2):
        start = time.perf_counter()
        results = pool.run_all(specs, workers=workers)
        rates[workers] = len(results) / (time.perf_counter() - start)
    radius = np.array([r.scalars["min_bend_radius"] for r in results])
    film = film_limit(ctx.robot, params.selected_surface)
    solver = params.acquire.solver
    print(f"{n} sampled {ctx.name} trajectories, {sim_seconds:.2f} s simulated, N = {solver.nodes}")
    print(f"one core, in process: median {per_sample:.3f} s/sample (max {np.max(one_core):.3f})")
    before = float(np.median(one_core_reference))
    change = np.median(np.array(one_core) / np.array(one_core_reference))
    print(
        f"  vs the reference {revision[:10]}: {before:.3f} s/sample, {change:.2f}x sample by "
        f"sample; channels identical in {identical} of {n}"
    )
    ratio20 = per_sample / float(np.median(baseline))
    print(f"  vs N = 20 (baseline): {np.median(baseline):.3f} s/sample, {ratio20:.2f}x")
    ratio_on = per_sample / float(np.median(one_core_all_on))
    print(
        f"  vs every bond connector on (baseline): {np.median(one_core_all_on):.3f} s/sample, "
        f"{ratio_on:.2f}x"
    )
    for figure in ("peak_pull", "peak_body_acc", "landing_pre_pressure", "min_bend_radius"):
        change = [relative_change(a[figure], b[figure]) for a, b in zip(idle, all_on, strict=True)]
        moved = sum(c > 0 for c in change)
        print(f"    {figure}: {moved} of {n} runs moved, largest {100 * max(change):.3f} %")
    print(f"pool, 1 worker:       {rates[1]:.2f} samples/s")
    ratio = rates[2] / rates[1]
    print(f"pool, 2 workers:      {rates[2]:.2f} samples/s, {ratio:.2f}x 1 worker, {ratio / 2:.0%}")
    print(f"1000 samples on 2 workers: {1000 / rates[2] / 60:.1f} min (estimate)")
    print(
        f"film bent below fc = {film.fc * 1e3:.0f} mm in {np.mean(radius < film.fc):.0%} and below "
        f"the film limit {film.radius * 1e3:.2f} mm in {np.mean(radius < film.radius):.0%} of "
        f"samples (median smallest radius {np.median(radius) * 1e3:.2f} mm)"
    )


if __name__ == "__main__":
    main(
        int(sys.argv[1]) if len(sys.argv) > 1 else 24,
        sys.argv[2] if len(sys.argv) > 2 else REFERENCE,
    )
