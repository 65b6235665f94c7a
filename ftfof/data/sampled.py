"""The sampled trajectory table `ftfof sample` writes (one row per trajectory: its control points
and the robot's fixed timing and P15), and the report of how the sampler got there."""

from __future__ import annotations

from typing import Any

import numpy as np
import pyarrow as pa

from ftfof.config import Sample
from ftfof.data.schema import TRAJECTORIES
from ftfof.robot import RobotContext
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.sampling import SampleResult


def trajectory_table(ctx: RobotContext, X: np.ndarray) -> pa.Table:
    """The rows ``X`` (m) of ``ctx``'s robot as the acquisition reads them."""
    n = len(X)
    timing = ctx.robot.timing
    columns = {
        "sample_id": np.arange(n, dtype=np.int64),
        "robot": [ctx.name] * n,
        **{name: X[:, j] for j, name in enumerate(DECISION_NAMES)},
        "T1": np.full(n, timing.T1),
        "T2": np.full(n, timing.T2),
        "T3": np.full(n, timing.T3),
        "P15x": np.full(n, ctx.policy.p15[0]),
        "P15z": np.full(n, ctx.policy.p15[1]),
    }
    return pa.Table.from_pydict(columns, schema=TRAJECTORIES)


def sample_report(
    ctx: RobotContext, result: SampleResult, cfg: Sample, recheck_hz: float, seconds: float
) -> dict[str, Any]:
    """What the sampler drew and why it refused the rest, per rule."""
    return {
        "robot": ctx.name,
        "samples": len(result.X),
        "draws": result.draws,
        "acceptance_rate": result.acceptance_rate,  # per draw over the rule-shaped region
        "box_acceptance_rate": result.box_acceptance,  # estimated, per plain box draw
        "rejected_by_fine_recheck": result.rejected_by_fine_recheck,
        "recheck_hz": recheck_hz,
        "design": cfg.design,
        "free_variables": list(ctx.policy.free_names),
        "rejected_by_constraint": result.rejected_by,
        "rejected_by_kind": result.rejected_by_kind,
        # sampled-trajectory rules run only on the draws that pass the control-point rules
        "evaluated_by_constraint": result.evaluated_by,
        "pass_fraction_by_constraint": result.pass_fraction,
        "limits": ctx.limits.summary(),
        "seconds": round(seconds, 3),
    }
