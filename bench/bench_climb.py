"""Climb speed (goal: an 8-step climb in <= 30 s on one core at the acquisition's solver step),
beside the platform's single step (one acquisition sample of the same trajectory), in this
process. Also per simulated second, and the climb's share that is Exudyn's own solve.

Run: python bench/bench_climb.py [baseline]   (default polynomial)
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.climb.simulate import climb
from ftfof.evaluate.pick import Source
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.climb import climb_spec
from ftfof.pipeline.params_file import load_params
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import baseline_specs
from stages.runtime import tune_allocator


def main(baseline: str) -> None:
    tune_allocator()
    root = Path(__file__).resolve().parents[1]
    params = load_params(root / "params.yaml")
    ctx = context_of(params)
    platform_spec = baseline_specs(bench(params, ctx), baseline_trajectories(params, ctx),
                                   [baseline])[0]  # fmt: skip
    simulate(platform_spec)  # warm-up: imports, numba cache
    start = time.perf_counter()
    sample = simulate(platform_spec)
    platform = time.perf_counter() - start
    _, spec = climb_spec(params, Source(baseline=baseline), root / "data/polish/optimize")
    start = time.perf_counter()
    run = climb(spec)
    whole = time.perf_counter() - start
    simulated = float(run.channels["t"][-1])
    per_step = platform_spec.end_time
    print(f"{baseline} on {params.robot} / {params.surface}, {params.acquire.solver.nodes} film "
          f"elements, step {params.acquire.solver.step:g} s")  # fmt: skip
    print(f"platform, one step ({per_step:.2f} s simulated): {platform:8.2f} s ({sample.status})")
    state = f"fell at {simulated:.2f} s: {run.fall_reason}" if run.fell else "climbed"
    print(
        f"climb, {spec.climb.steps} steps ({simulated:.2f} s simulated): {whole:8.2f} s ({state})"
    )
    climb_rate, platform_rate = whole / simulated, platform / per_step
    print(f"  per simulated second: climb {climb_rate:6.2f} s, platform {platform_rate:6.2f} s"
          f"  ({climb_rate / platform_rate:.1f}x)")  # fmt: skip
    if run.fell:
        full = spec.climb.steps * run.gait.period + run.gait.start
        print(f"  projected to the whole {full:.2f} s climb: {whole / simulated * full:8.2f} s")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "polynomial")
