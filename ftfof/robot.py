"""The selected robot, resolved once per run: preset, limits, rules and constraint policy."""

from __future__ import annotations

from dataclasses import dataclass

from ftfof.config import Feasibility, Protocol, Robot, Surface
from ftfof.kinematics.limits import RobotLimits, resolve_limits
from ftfof.rules import FootRules, foot_rules
from ftfof.trajectory.policy import ConstraintPolicy


@dataclass(frozen=True)
class RobotContext:
    name: str
    robot: Robot
    limits: RobotLimits  # the leg's reachable positions and velocities (Ppl, Vpl)
    policy: ConstraintPolicy  # the trajectory rules the search and the sampler keep
    rules: FootRules  # what a simulated step must survive on this surface


def robot_context(
    name: str,
    robot: Robot,
    surface: Surface,
    protocol: Protocol,
    feasibility: Feasibility,
    limits_seed: int,
) -> RobotContext:
    """Resolve Ppl/Vpl, build the policy and the rules; raises InfeasibleRobotError before any
    output."""
    limits = resolve_limits(robot, name, seed=limits_seed)
    return RobotContext(
        name,
        robot,
        limits,
        ConstraintPolicy(robot, limits, feasibility, name),
        foot_rules(robot, surface, protocol),
    )
