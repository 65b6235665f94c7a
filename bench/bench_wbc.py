"""One control step of the contact-force QP (ftfof.climb.control.forces; goal: median <= 2 ms),
warm-started as the controller runs it, beside the same steps each solved cold.

The problem varies slowly, as at a 1 kHz control rate: the params' robot on all four feet, the
body advancing a quarter stride over the 1000 steps (each foot's stroke and Jacobian move with
it), the trunk's wrench the weight plus a 2 Hz sway. Timed: Stance to Distribution (the QP's
assembly, the solve, the torques), one thread.
Run: python bench/bench_wbc.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.climb.control.forces import ForceDistributor, Stance
from ftfof.climb.legs import sagittal_chain
from ftfof.pipeline.params_file import load_params

ROOT = Path(__file__).resolve().parents[1]
STEPS = 1000
RATE = 1000.0  # Hz, the control rate the problem's drift assumes
MASS = 0.8  # kg, the M3F climber's estimate
START = np.array([0.02, 0.08, 0.05, 0.11])  # each foot along its stroke, m (FL FR HL HR)
FRICTION, ADHESION, PULL_OFF, WEIGHTS = 0.6, 8.0, 8.0, (1.0, 1e-3)


def problems() -> list[tuple[Stance, np.ndarray]]:
    """The 1000 steps' stances and wrenches."""
    robot = load_params(ROOT / "params.yaml").selected_robot
    climber = robot.climber
    chain = sagittal_chain(robot.leg, climber.torque_limits, robot.platform.foot.ankle_height)
    hips = np.array([1.0, 1.0, -1.0, -1.0]) * climber.hip_spacing / 2
    out = []
    for k in range(STEPS):
        t = k / RATE
        stroke = START - 0.03 * k / STEPS  # the body advances, the feet stay: strokes shorten
        feet = np.stack([stroke, np.zeros(4)], axis=1)
        offset = feet - chain.hip + np.stack([hips, np.zeros(4)], axis=1)
        stance = Stance(
            offset,
            chain.leg.jacobian(chain.leg.inverse(feet)),
            np.full(4, FRICTION),
            np.full(4, ADHESION),
            np.tile(chain.torque_limits, (4, 1)),
            np.tile(WEIGHTS, (4, 1)),
            np.full(4, PULL_OFF),
        )
        sway = np.sin(2 * np.pi * 2.0 * t)
        out.append((stance, np.array([MASS * (9.81 + 0.5 * sway), 0.2 * sway, 0.02 * sway])))
    return out


def timed(solver: ForceDistributor, steps, cold: bool) -> tuple[np.ndarray, np.ndarray]:
    """Each step's wall time and iterations; ``cold`` forgets the solver before each."""
    seconds, iterations = np.empty(len(steps)), np.empty(len(steps))
    for k, (stance, wrench) in enumerate(steps):
        if cold:
            solver.reset()
        start = time.perf_counter()
        out = solver.solve(stance, wrench)
        seconds[k] = time.perf_counter() - start
        if not out.solved:
            raise RuntimeError(f"step {k}: {out.status}")
        iterations[k] = out.iterations
    return seconds, iterations


def main() -> None:
    steps = problems()
    timed(ForceDistributor(), steps[:50], cold=False)  # warm-up: imports, first allocations
    for label, cold in (("warm-started", False), ("cold", True)):
        seconds, iterations = timed(ForceDistributor(), steps, cold)
        print(
            f"{label:<13} median {1e3 * np.median(seconds):7.3f} ms, p95 "
            f"{1e3 * np.percentile(seconds, 95):7.3f} ms, max {1e3 * seconds.max():7.3f} ms; "
            f"{iterations.mean():.1f} iterations a step  (goal: median <= 2 ms)"
        )


if __name__ == "__main__":
    main()
