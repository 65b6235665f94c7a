"""Can the robot run it? Each Table I trajectory judged by the robot's constraint policy, and the
reference the changes are taken against chosen among those it can run (FTFOF §VII: the common
trajectories cannot meet MST-Q's vertical detachment)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ftfof.robot import RobotContext
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.piecewise import Sampled


def admitted(
    ctx: RobotContext,
    baselines: Mapping[str, Sampled],
    bezier: Mapping[str, np.ndarray],
) -> dict[str, list[str]]:
    """Per trajectory name, the robot's rules it breaks ([]: the robot can run it): the common
    ``baselines`` on the path rules, the ``bezier`` rows (the optimum, the published one) on
    every rule."""
    out = {name: ctx.policy.path_failures(t) for name, t in baselines.items()}
    for name, X in bezier.items():
        out[name] = ctx.policy.check(np.asarray(X, dtype=float)).failed(0)
    return out


def reference_for(
    requested: str,
    preset: str | None,
    breaks: Mapping[str, list[str]],
    detachment: Mapping[str, float],
) -> tuple[str, str]:
    """The baseline Table I's changes are taken against, and why: the robot preset's, else the
    ``requested`` one (evaluate.reference) where the robot can run it, else the runnable baseline
    with the lowest peak detachment force (Table I's first figure); with none runnable, the
    requested one, said so."""
    runnable = [n for n in detachment if not breaks.get(n)]
    if preset is not None:
        return preset, f"the robot preset's reference ({preset})"
    if requested in runnable:
        return requested, f"evaluate.reference ({requested})"
    if runnable:
        best = min(runnable, key=lambda n: detachment[n])
        why = (
            f"{requested} breaks the robot's rules ({'; '.join(breaks[requested][:2])}); "
            f"{best} is the runnable baseline with the lowest detachment force"
        )
        return best, why
    return (
        requested,
        "no common trajectory meets the robot's rules: changes are against one it cannot run",
    )


def climbable(
    ctx: RobotContext,
    baselines: Mapping[str, Sampled],
    bezier: Mapping[str, np.ndarray],
    breaks: Mapping[str, list[str]],
) -> tuple[dict[str, tuple[Sampled, np.ndarray | None]], dict[str, str]]:
    """Table I's trajectories the robot can run (per name the trajectory and its decision row,
    None for a baseline), and the others with the first rules (:func:`admitted`) each breaks."""
    trajectories: dict[str, tuple[Sampled, np.ndarray | None]] = {
        name: (trajectory, None) for name, trajectory in baselines.items()
    }
    for name, X in bezier.items():
        trajectories[name] = (BezierTrajectory(ctx.policy, X), X)
    runnable = {n: t for n, t in trajectories.items() if not breaks.get(n)}
    skipped = {n: "; ".join(breaks[n][:2]) for n in trajectories if n not in runnable}
    return runnable, skipped
