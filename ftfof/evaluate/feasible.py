"""Can the robot run it? Each Table I trajectory judged by the robot's constraint policy, and the
reference the changes are taken against chosen among those it can run (FTFOF §VII: the common
trajectories cannot meet MST-Q's vertical detachment)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ftfof.robot import RobotContext
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
