"""Which trajectory a command runs (`ftfof export`, `ftfof climb`): a common baseline by name,
control points typed on the command line, or a row of the front (the chosen optimum by default),
each with its decision row where it has one and the metadata of where it came from."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ftfof.errors import ParamsError
from ftfof.evaluate.run import Inputs, decision
from ftfof.robot import RobotContext
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.piecewise import Sampled

# (name, trajectory, decision row or None for an analytic baseline, metadata of where it came from)
Picked = tuple[str, Sampled, np.ndarray | None, dict[str, Any]]


@dataclass(frozen=True)
class Source:
    """Which trajectory: the optimum (``row`` None), a front row, a baseline, or points (m)."""

    row: int | None = None
    baseline: str | None = None
    points: np.ndarray | None = None


def named_baseline(baselines: Mapping[str, Sampled], name: str) -> Picked:
    """The common trajectory ``name`` of ``baselines``."""
    if name not in baselines:
        raise ParamsError("--baseline", f"unknown baseline {name!r} (have {', '.join(baselines)})")
    note = {"constraint_policy": "not checked: an analytic baseline is not a Bezier row"}
    return name, baselines[name], None, note


def typed_points(ctx: RobotContext, points: np.ndarray) -> Picked:
    """The Bezier of control ``points`` (m) on the robot."""
    X = np.asarray(points, dtype=float)
    return "points", BezierTrajectory(ctx.policy, X), X, {}


def front_row(ctx: RobotContext, inputs: Inputs, row: int | None, where: Path) -> Picked:
    """Row ``row`` of the front in ``inputs`` (read from ``where``), the chosen optimum when
    ``row`` is None."""
    chosen = inputs.optimum["front_row"] if row is None else row
    if chosen not in inputs.front.index:
        raise ParamsError(
            "--row", f"{chosen} is not a row of {where} (0..{inputs.front.index.max()})"
        )
    X = decision(inputs, chosen)
    name = "optimum" if row is None else f"row{chosen}"
    front = inputs.front
    extra = {
        "front_row": int(chosen),
        "origin": str(front.loc[chosen, "origin"]) if "origin" in front else "front",
        "optimum_digest": inputs.digest,
        "models_digest": inputs.optimum["models_digest"],
    }
    return name, BezierTrajectory(ctx.policy, X), X, extra
