"""`ftfof export`: any trajectory (the optimum, a front row, a baseline, typed points) for a
robot's controller, with the metadata a lab notebook needs, refused where the robot cannot run
it."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from ftfof.config import Params
from ftfof.digests import json_sha256
from ftfof.errors import DataError
from ftfof.evaluate.export import export_metadata, render, runnable, simulated_figures
from ftfof.evaluate.pick import Source
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.trajectory import trajectory_of


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
