"""Which trajectory a command runs: the one resolver `ftfof simulate`, `export` and `climb` share,
reading what :mod:`ftfof.evaluate.pick` picks from (the baselines, the front, the sampled table)."""

from __future__ import annotations

from pathlib import Path

from ftfof.config import Params
from ftfof.data.schema import TRAJECTORIES
from ftfof.evaluate.pick import (
    Picked,
    Source,
    front_row,
    named_baseline,
    sampled_row,
    typed_points,
)
from ftfof.files import read_table
from ftfof.pipeline.artefacts import POLISH_READS, read_optimum
from ftfof.pipeline.bench import baseline_trajectories
from ftfof.pipeline.catalog import path
from ftfof.robot import RobotContext

SAMPLED = path("trajectories")
FRONT = path("polish_optimize")


def trajectory_of(
    params: Params,
    ctx: RobotContext,
    source: Source,
    optimize: Path = FRONT,
    trajectories: Path = SAMPLED,
) -> Picked:
    """(name, trajectory, decision row or None for an analytic baseline, metadata of where it
    came from): this run's baselines, typed points, a row of the sampled table in
    ``trajectories``, or a row of the front in ``optimize`` (the chosen optimum by default)."""
    if source.baseline is not None:
        return named_baseline(baseline_trajectories(params, ctx), source.baseline)
    if source.points is not None:
        return typed_points(ctx, source.points)
    if source.sample is not None:
        return sampled_row(
            ctx, read_table(trajectories, TRAJECTORIES, "trajectory table"), source.sample
        )
    return front_row(ctx, read_optimum(optimize, ctx.name, POLISH_READS), source.row, optimize)
