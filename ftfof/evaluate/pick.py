"""Which trajectory a command runs (`ftfof simulate`, `export`, `climb`): a common baseline by
name, control points typed on the command line, a row of the sampled table, or a row of the front
(the chosen optimum by default), each with its decision row where it has one and the metadata of
where it came from. :func:`ftfof.pipeline.trajectory.trajectory_of` reads what these pick from."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from ftfof.errors import ParamsError
from ftfof.evaluate.run import Inputs, decision
from ftfof.robot import RobotContext
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.piecewise import Sampled

# (name, trajectory, decision row or None for an analytic baseline, metadata of where it came from)
Picked = tuple[str, Sampled, np.ndarray | None, dict[str, Any]]


@dataclass(frozen=True)
class Source:
    """Which trajectory: the optimum (all None), a front ``row``, a ``sample`` row of the sampled
    table, a ``baseline``, or ``points`` (m; typed in ``unit``)."""

    row: int | None = None
    baseline: str | None = None
    points: np.ndarray | None = None
    sample: int | None = None
    unit: str = "m"


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


def sampled_row(ctx: RobotContext, table: pa.Table, row: int) -> Picked:
    """Row ``row`` of the sampled trajectory table."""
    if not 0 <= row < table.num_rows:
        raise ParamsError("--row", f"{row} is outside 0..{table.num_rows - 1}")
    X = np.array([table.column(n)[row].as_py() for n in DECISION_NAMES])
    return f"row{row}", BezierTrajectory(ctx.policy, X), X, {"sample_row": row}


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
