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
from ftfof.evaluate.export import (
    ExportRateError,
    controller_trajectory,
    limit_breaches,
    render,
)
from ftfof.evaluate.run import decision
from ftfof.kinematics.legs import build_leg
from ftfof.pipeline.artefacts import POLISH_READS, read_optimum
from ftfof.pipeline.bench import baseline_trajectories, context_of
from ftfof.robot import RobotContext
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.piecewise import Sampled
from ftfof.version import __version__

FRAME = (
    "trajectory frame: origin at the foot's start point P0, x along the wall in the step's "
    "direction, z away from the wall"
)
UNITS = {"t": "s", "x, z": "m", "vx, vz": "m/s", "q": "rad", "dq": "rad/s"}


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
    the robot cannot run (its constraint policy at that rate, a joint's range or speed) is
    refused, naming the rule."""
    ctx = context_of(params)
    leg = build_leg(ctx.robot.leg)
    name, trajectory, X, extra = trajectory_of(params, ctx, source, optimize)
    if X is not None:
        failed = ctx.policy.at_rate(rate_hz).check(X).failed(0)
        if failed:
            raise ParamsError(name, f"{ctx.name} cannot run it: {'; '.join(failed[:3])}")
    try:
        out = controller_trajectory(trajectory, ctx.policy.timing.T3, leg, rate_hz)
    except ExportRateError as err:
        raise ParamsError("--rate", str(err)) from None
    except ValueError as err:
        raise ParamsError(name, str(err)) from None
    breaches = limit_breaches(out, leg)
    if breaches:
        raise ParamsError(name, f"{ctx.name}'s leg cannot run it: {'; '.join(breaches[:3])}")
    metadata = {
        "ftfof": __version__,
        "robot": ctx.name,
        "leg": ctx.robot.leg.type,
        "surface": params.surface,
        "trajectory": name,
        "frame": FRAME,
        "frame_id": f"{ctx.name}_foot_start",
        "units": UNITS,
        "rate_hz": rate_hz,
        "duration_s": ctx.policy.timing.T3,
        "params_hash": json_sha256(params.model_dump(mode="json"), 16),
        **extra,
        "simulated": _simulated(metrics, name, extra.get("front_row")),
    }
    if X is not None:
        metadata["control_points_mm"] = {
            n: round(1e3 * float(v), 6) for n, v in zip(DECISION_NAMES, X, strict=True)
        }
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
    table = summary.get("table", {})
    key = "optimum" if row is not None and row == summary.get("optimum_front_row") else name
    if key in table:
        return {k: v for k, v in table[key].items() if not k.endswith("_change")}
    members = summary.get("front_simulated", {}).get("members", [])
    for member in members:
        if row is not None and member.get("row") == row:
            figures = ("peak_pull", "jitter", "min_bend_radius", "max_clearance")
            return {k: member[k] for k in figures if k in member}
    return "not simulated by evaluate"
