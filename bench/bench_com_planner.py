"""The one-step CoM planner's solve time (issue 40 goal: a median under 1 ms in Python).

Random steps of the params' robot (its mass; hips, hip height and stride each scaled by
0.8-1.2), drawn with a seeded generator: every foot somewhere on its stance stroke, one of them
stepping up 0.5-1 stride, the CoM's goal up to half a stride up the wall and +-5 mm off it,
pads of mu 0.45-0.8 and F_adh 5-60 N (the landing spot's its own), phases of 0.3-0.8 s,
0.5-1.5 s and 0.3-0.8 s. The feasible ones are kept until ``--problems``; each is planned once
(plan_step) and re-planned once from its own state halfway through the swing with every pad's
mu 10 % lower (replan_swing, infeasible answers included: they are answers too).

Run: python bench/bench_com_planner.py [--problems 1000] [--seed 0]
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.climb.control.com_step import Foothold, Step
from ftfof.climb.control.cones import InfeasibleStepError
from ftfof.climb.control.planner import feasible_interval, plan_step, replan_swing
from ftfof.climb.simulate import chain_of
from ftfof.demand import robot_mass
from ftfof.pipeline.params_file import load_params

ROOT = Path(__file__).resolve().parents[1]


def random_step(rng: np.random.Generator, mass: float, half: float, hip: np.ndarray, stride: float):
    """One step of a robot like ours (see the module's docstring)."""
    scale = rng.uniform(0.8, 1.2, 3)
    hips = half * scale[0] * np.array([1.0, 1.0, -1.0, -1.0])
    stroke = stride * scale[2]
    x = hips - hip[0] + rng.uniform(0.0, stroke, 4)
    swing = int(rng.integers(4))
    mu, adhesion = rng.uniform(0.45, 0.8, 5), rng.uniform(5.0, 60.0, 5)
    feet = tuple(Foothold(np.array([x[i], 0.0]), mu[i], adhesion[i]) for i in range(4))
    landing = Foothold(np.array([x[swing] + rng.uniform(0.5, 1.0) * stroke, 0]), mu[4], adhesion[4])
    start = np.array([0.0, hip[1] * scale[1]])
    goal = start + np.array([rng.uniform(0.0, stroke / 2), rng.uniform(-0.005, 0.005)])
    durations = (rng.uniform(0.3, 0.8), rng.uniform(0.5, 1.5), rng.uniform(0.3, 0.8))
    return Step(mass, start, goal, feet, swing, landing, durations)


def feasible_steps(count: int, seed: int) -> tuple[list[Step], int]:
    """``count`` feasible random steps and how many were drawn to find them."""
    params = load_params(ROOT / "params.yaml")
    robot = params.selected_robot
    assert robot.climber is not None
    args = (robot_mass(robot), robot.climber.hip_spacing / 2, chain_of(robot).hip, robot.landing.x)
    rng = np.random.default_rng(seed)
    kept, drawn = [], 0
    while len(kept) < count:
        step = random_step(rng, *args)
        drawn += 1
        if not feasible_interval(step).empty:
            kept.append(step)
    return kept, drawn


def slower(step: Step) -> Step:
    """The step with every pad's mu 10 % lower."""
    feet = tuple(dataclasses.replace(f, mu=0.9 * f.mu) for f in step.feet)
    return dataclasses.replace(step, feet=feet)


def timed_plan(step: Step) -> float:
    started = time.perf_counter()
    plan_step(step)
    return time.perf_counter() - started


def timed_replan(step: Step) -> float:
    """Seconds to re-plan halfway through the swing, from the plan's own state."""
    plan = plan_step(step)
    T1, T2, _ = step.durations
    p, v, _ = plan.state(np.array([T1 + T2 / 2]))
    changed = slower(step)
    started = time.perf_counter()
    with contextlib.suppress(InfeasibleStepError):  # an infeasible answer is an answer too
        replan_swing(changed, plan.direction, T2 / 2, p[0], v[0])
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problems", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    steps, drawn = feasible_steps(args.problems, args.seed)
    plan_step(steps[0])  # warm-up: lazy imports, caches
    plans = np.array([timed_plan(s) for s in steps]) * 1e6
    replans = np.array([timed_replan(s) for s in steps]) * 1e6
    print(f"{len(steps)} feasible steps of {drawn} drawn (seed {args.seed})")
    for label, us in (("plan_step", plans), ("replan_swing, mid-swing", replans)):
        p10, p50, p90 = np.percentile(us, [10, 50, 90])
        print(f"{label:<26} median {p50:7.1f} us   (10-90 %: {p10:.1f}-{p90:.1f} us)")


if __name__ == "__main__":
    main()
