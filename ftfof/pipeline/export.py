"""`ftfof export`: any trajectory (the optimum, a front row, a baseline, typed points) for a
robot's controller, with the metadata a lab notebook needs, refused where the robot cannot run
it."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ftfof.config import Params
from ftfof.digests import json_sha256
from ftfof.errors import DataError, ParamsError
from ftfof.evaluate.export import export_metadata, render, runnable, simulated_figures
from ftfof.evaluate.run import decision
from ftfof.pipeline.artefacts import POLISH_READS, read_optimum
from ftfof.pipeline.bench import baseline_trajectories, context_of
from ftfof.robot import RobotContext
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.piecewise import Sampled


@dataclass(frozen=True)
class Source:
    """Which trajectory: the optimum (``row`` None), a front row, a baseline, or points (m)."""

    row: int | None = None
    baseline: str | None = None
    points: np.ndarray | None = None


@dataclass(frozen=True)
class Exported:
    name: str  # for the file: optimum, row212, polynomial, points
    text: str
    rows: int


def export(
    params: Params, source: Source, rate_hz: float, fmt: str, optimize: Path, metrics: Path
) -> Exported:
    """``source`` sampled at ``rate_hz`` through the leg's IK, rendered as ``fmt``; a trajectory
    the robot cannot run is refused, naming the rule (:func:`ftfof.evaluate.export.runnable`)."""
    ctx = context_of(params)
    name, trajectory, X, extra = trajectory_of(params, ctx, source, optimize)
    out = runnable(ctx, name, trajectory, X, rate_hz)
    params_hash = json_sha256(params.model_dump(mode="json"), 16)
    simulated = _simulated(metrics, name, extra.get("front_row"))
    metadata = export_metadata(ctx, params.surface, name, rate_hz, params_hash, extra, simulated, X)
    return Exported(name, render(out, metadata, fmt), int(out.table.shape[0]))


def trajectory_of(
    params: Params, ctx: RobotContext, source: Source, optimize: Path
) -> tuple[str, Sampled, np.ndarray | None, dict[str, Any]]:
    """(name, trajectory, decision row or None for an analytic baseline, metadata of where it
    came from)."""
    if source.baseline is not None:
        baselines = baseline_trajectories(params, ctx)
        if source.baseline not in baselines:
            raise ParamsError(
                "--baseline", f"unknown baseline {source.baseline!r} (have {', '.join(baselines)})"
            )
        note = {"constraint_policy": "not checked: an analytic baseline is not a Bezier row"}
        return source.baseline, baselines[source.baseline], None, note
    if source.points is not None:
        X = np.asarray(source.points, dtype=float)
        return "points", BezierTrajectory(ctx.policy, X), X, {}
    inputs = read_optimum(optimize, ctx.name, POLISH_READS)
    row = inputs.optimum["front_row"] if source.row is None else source.row
    if row not in inputs.front.index:
        raise ParamsError(
            "--row", f"{row} is not a row of {optimize} (0..{inputs.front.index.max()})"
        )
    X = decision(inputs, row)
    name = "optimum" if source.row is None else f"row{row}"
    extra = {
        "front_row": int(row),
        "origin": str(inputs.front.loc[row, "origin"]) if "origin" in inputs.front else "front",
        "optimum_digest": inputs.digest,
        "models_digest": inputs.optimum["models_digest"],
    }
    return name, BezierTrajectory(ctx.policy, X), X, extra


def _simulated(metrics: Path, name: str, row: int | None) -> dict[str, float] | str:
    """The simulator's Table I figures for this trajectory from ``metrics`` (evaluate's), where
    evaluate simulated it."""
    if not metrics.exists():
        return "not simulated by evaluate (no metrics file)"
    try:
        summary = json.loads(metrics.read_text())
    except ValueError as err:
        raise DataError(str(metrics), f"unreadable metrics ({err})") from None
    return simulated_figures(summary, name, row)
