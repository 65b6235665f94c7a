"""The selected robot, resolved once per run: preset, limits and constraint policy."""

from __future__ import annotations

from dataclasses import dataclass

from ftfof.config import Params, Robot
from ftfof.kinematics.limits import RobotLimits, resolve_limits
from ftfof.seeds import seed_for
from ftfof.trajectory.policy import ConstraintPolicy


@dataclass(frozen=True)
class RobotContext:
    name: str
    robot: Robot
    limits: RobotLimits
    policy: ConstraintPolicy


def robot_context(params: Params) -> RobotContext:
    """Resolve Ppl/Vpl and build the policy; raises InfeasibleRobotError before any output."""
    name, robot = params.robot, params.selected_robot
    limits = resolve_limits(robot, name, seed=seed_for(params.base.seed, "limits"))
    return RobotContext(
        name, robot, limits, ConstraintPolicy(robot, limits, params.feasibility, name)
    )
