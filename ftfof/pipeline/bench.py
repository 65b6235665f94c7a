"""What a run builds from its params, one way for every command: the robot context, the simulated
bench and the baselines on it."""

from __future__ import annotations

from ftfof.config import Params, Surface
from ftfof.robot import RobotContext, robot_context
from ftfof.seeds import seed_for
from ftfof.sim.spec import Bench
from ftfof.trajectory.baselines import common_trajectories
from ftfof.trajectory.piecewise import Sampled


def context_of(params: Params) -> RobotContext:
    """The selected robot on the selected surface."""
    return robot_context(
        params.robot,
        params.selected_robot,
        params.selected_surface,
        params.platform.protocol,
        params.feasibility,
        seed_for(params.base.seed, "limits"),
    )


def bench(params: Params, ctx: RobotContext, surface: Surface | None = None) -> Bench:
    """The platform with the selected robot on ``surface`` (default: the selected surface)."""
    return Bench(
        ctx.robot,
        surface or params.selected_surface,
        params.platform,
        params.acquire,
        params.base.seed,
    )


def baseline_trajectories(params: Params, ctx: RobotContext) -> dict[str, Sampled]:
    """The common trajectories every optimum is compared with, from this run's seed."""
    return common_trajectories(
        ctx.policy, params.baselines, seed_for(params.base.seed, "baselines")
    )


__all__ = [
    "baseline_trajectories",
    "bench",
    "context_of",
]
