"""`sample_feasible` at paper scale (n = 1000) for both robots vs plain box draws.

The baseline draws the same scrambled-Sobol design over the raw free-variable box and screens it
with every rule (the sampler before the rule-shaped map, without its 1 kHz recheck). Box draws
need ~6e7 draws for MST-M3F at n = 1000, so the baseline runs a smaller n in the same process and
the ratio is of seconds per accepted trajectory.
Run: python bench/bench_sample.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import yaml
from scipy.stats import qmc

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.config import Params
from ftfof.pipeline.bench import context_of
from ftfof.seeds import seed_for
from ftfof.trajectory.policy import ConstraintPolicy
from ftfof.trajectory.sampling import sample_feasible
from stages.runtime import tune_allocator

N = 1000
BOX_N = {"mst_m3f": 20, "mst_q": 200}  # box draws: ~1.3e6 and ~4e4 draws


def box_draws(policy: ConstraintPolicy, n: int, seed: int, batch: int = 4096) -> int:
    """Draws the raw-box sampler needs for ``n`` trajectories that pass every rule."""
    engine = qmc.Sobol(policy.n_free, scramble=True, rng=np.random.default_rng(seed))
    span = policy.upper - policy.lower
    accepted = draws = 0
    while accepted < n:
        X = policy.expand(policy.lower + engine.random(batch) * span)
        accepted += int(policy.screen(X).feasible.sum())
        draws += batch
    return draws


def main() -> None:
    tune_allocator()  # as in every `ftfof` process
    raw = yaml.safe_load((Path(__file__).resolve().parents[1] / "params.yaml").read_text())
    print(f"{'robot':<8} {'sampler':<12} {'n':>5} {'draws':>11} {'acceptance':>11} {'s':>8}")
    for robot in ("mst_m3f", "mst_q"):
        params = Params.model_validate({**raw, "robot": robot})
        policy = context_of(params).policy
        seed = seed_for(params.base.seed, "sample")
        start = time.perf_counter()
        res = sample_feasible(policy, N, seed, max_draws=params.sample.max_draws)
        mapped = time.perf_counter() - start
        print(
            f"{robot:<8} {'shaped':<12} {N:>5} {res.draws:>11,} {res.acceptance_rate:>11.2e} "
            f"{mapped:>8.2f}   1 kHz recheck dropped {res.rejected_by_fine_recheck}, "
            f"box acceptance (estimated) {res.box_acceptance:.2e}"
        )
        n_box = BOX_N[robot]
        start = time.perf_counter()
        draws = box_draws(policy, n_box, seed)
        boxed = time.perf_counter() - start
        ratio = (boxed / n_box) / (mapped / N)
        print(
            f"{robot:<8} {'box':<12} {n_box:>5} {draws:>11,} {n_box / draws:>11.2e} "
            f"{boxed:>8.2f}   shaped is {ratio:.1f}x faster per trajectory "
            f"(box at n = {N}: ~{boxed / n_box * N:.0f} s)"
        )


if __name__ == "__main__":
    main()
