"""Vectorised trajectory evaluation vs one individual at a time (issue 2 goal: >= 20x).

Work per call: a 200 x 12 population at 256 time samples -> positions, velocities, fs5 and fs6.
Run: python bench/bench_trajectory.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import best_of, row
from ftfof.config import Timing
from ftfof.objectives import fs5_adhesion_path_length, fs6_bending
from ftfof.trajectory.bezier import evaluate
from stages.runtime import tune_allocator

POP, N_T = 200, 256
TIMING = Timing(T1=1 / 3, T2=2 / 3, T3=1.0)
P0, P15 = np.zeros(2), np.array([0.12, 0.0])
T = TIMING.grid(N_T)
X = np.array([2.3, 18.3, 31.4, 108.8, 123.7, 124.5, 23.6, 25.5, 29.0, 48.6, 30.5, 11.1]) / 1000
POPULATION = X + np.random.default_rng(0).normal(scale=0.002, size=(POP, 12))


def work(Xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = evaluate(Xs, P0, P15, TIMING, T)
    return fs5_adhesion_path_length(s.velocity, T, TIMING.T2, TIMING.T3), fs6_bending(
        s.position, 1e-9
    )


def vectorised() -> None:
    work(POPULATION)


def one_at_a_time() -> None:
    for i in range(POP):
        work(POPULATION[i : i + 1])


def main() -> None:
    tuned = tune_allocator()  # as in every `ftfof` process
    a = np.concatenate(work(POPULATION))
    b = np.concatenate([np.concatenate(work(POPULATION[i : i + 1])) for i in range(POP)])
    assert np.allclose(np.sort(a), np.sort(b))
    loop = best_of(one_at_a_time, repeats=3)
    vec = best_of(vectorised, repeats=10)
    print(f"population {POP} x 12, {N_T} time samples: positions, velocities, fs5, fs6")
    print(f"allocator tuned as in the pipeline: {tuned}")
    print(row("per-individual Python loop (baseline)", loop))
    print(row("vectorised over the population", vec, loop))


if __name__ == "__main__":
    main()
