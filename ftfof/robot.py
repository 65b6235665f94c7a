"""The selected robot, resolved once per run: preset, limits, rules and constraint policy; and
control points typed for it (a command line's ``--points``), checked against its rules."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ftfof.config import Feasibility, Protocol, Robot, Surface
from ftfof.demand import proof_pull
from ftfof.errors import InfeasibleRobotError, ParamsError
from ftfof.kinematics.legs import build_leg, within_limits
from ftfof.kinematics.limits import RobotLimits, resolve_limits
from ftfof.rules import FootRules, foot_rules
from ftfof.trajectory.bezier import DECISION_NAMES
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
    policy = ConstraintPolicy(robot, limits, feasibility, name)
    _stands_at_both_ends(name, robot, policy)
    _proof_within_the_pad(name, robot, surface)
    return RobotContext(name, robot, limits, policy, foot_rules(robot, surface, protocol))


def _proof_within_the_pad(name: str, robot: Robot, surface: Surface) -> None:
    """F_proof above the pad's whole strength sigma A (every bond fully preloaded, at rest) is
    a pull no landing can hold: the rule would refuse every trajectory after a whole search."""
    force = proof_pull(robot)
    strength = surface.strength * robot.pad_area
    if force is not None and force > strength:
        raise InfeasibleRobotError(
            f"robots.{name}.proof.safety_factor",
            f"F_proof {force:.2f} N is above the pad's strength on this surface, sigma A ="
            f" {strength:.2f} N, which no landing can hold: lower the safety factor",
        )


def _stands_at_both_ends(name: str, robot: Robot, policy: ConstraintPolicy) -> None:
    """Every trajectory starts at P0 and lands at P15: a leg that cannot hold the foot at either
    within its joint ranges can run none, which the joint rule would find only after the
    sampler's whole draw budget (minutes)."""
    leg = build_leg(robot.leg)
    for label, point in (("P0", policy.p0), ("P15", policy.p15)):
        theta = leg.inverse(point)
        if not (np.all(np.isfinite(theta)) and within_limits(theta, leg.joint_limits)):
            angles = ", ".join(f"{a:.2f}" for a in theta)
            raise InfeasibleRobotError(
                f"robots.{name}.leg",
                f"the leg cannot hold the foot at {label} within its joint ranges (joints at "
                f"[{angles}] rad, ranges {leg.joint_limits.tolist()}): no trajectory can start "
                "or land there",
            )


def parse_points(text: str, unit: str) -> np.ndarray:
    """The 12 control values P3x..P12x, P3z..P12z as written on a command line, in metres; a NaN
    or an infinity is refused by name (the robot's rules would refuse it, but naming a shape rule
    it broke, not the value)."""
    scale = {"m": 1.0, "mm": 1e-3}.get(unit)
    if scale is None:
        raise ParamsError("--unit", f"must be m or mm (got {unit!r})")
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise ParamsError("--points", "must be 12 comma-separated numbers") from None
    if len(values) != 12:
        raise ParamsError("--points", f"needs 12 values P3x..P12z (got {len(values)})")
    bad = [f"{n} is {v}" for n, v in zip(DECISION_NAMES, values, strict=True) if not np.isfinite(v)]
    if bad:
        raise ParamsError("--points", f"{', '.join(bad)}: every control value must be finite")
    return np.array(values) * scale


def check_points(X: np.ndarray, unit: str, ctx: RobotContext, allow_infeasible: bool) -> list[str]:
    """The rules of ``ctx``'s policy that the control points ``X`` (m) break; refused unless
    ``allow_infeasible``. Values a thousand times off the robot's reach are refused either way,
    with the unit they were most likely meant in."""
    reach = float(np.max(ctx.limits.position))
    size = float(np.max(np.abs(X)))
    if unit == "m" and size > 10 * reach and size * 1e-3 <= 2 * reach:
        raise ParamsError(
            "--points",
            f"reach {size:g} m, {size / reach:.0f} times the robot's {reach:g} m: they look like "
            "millimetres (add --unit mm)",
        )
    if unit == "mm" and 0 < size < reach / 100 and size * 1e3 <= 2 * reach:
        raise ParamsError(
            "--points",
            f"reach {1e3 * size:g} mm, 1/{reach / size:.0f} of the robot's {1e3 * reach:g} mm: "
            "they look like metres (drop --unit mm)",
        )
    failed = ctx.policy.check(X).failed(0)
    if failed and not allow_infeasible:
        raise ParamsError(
            "--points",
            f"{ctx.name} cannot run them: {'; '.join(failed[:3])} "
            "(--allow-infeasible simulates them anyway, marked as such)",
        )
    return failed
