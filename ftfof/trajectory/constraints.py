"""The table of named constraints of one robot (FTFOF §III.B, §VI.A): each a vectorised
violation measure (> 0 means violated) over a population of full 12-value decision vectors,
covering the five constraint kinds of the paper plus the bending measure fs6.

The box bounds and the rules between control points are read off the decision vector; swing
containment is checked on the *sampled* trajectory (the published MST-M3F optimum has swing
control points above Pplz while its curve stays below), and so are md on the path (``md_path``,
switchable per robot) and the hairpin guards ``min_path_radius`` and ``no_cusp`` that keep fs6
from being passed between samples (:mod:`ftfof.trajectory.rules`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.kinematics.legs import build_leg, joint_excess
from ftfof.kinematics.limits import RobotLimits
from ftfof.objectives import fs6_bending
from ftfof.trajectory.feasibility import Bound, Constraint, Population
from ftfof.trajectory.rules import md_path_violation, path_radius_violation, reversal_violation

Array = NDArray[np.float64]
Rule = tuple[str, str, Callable[[Population], Array]]  # kind, name, violation


def constraint_table(
    robot: config.Robot,
    limits: RobotLimits,
    feasibility: config.Feasibility,
    t: Array,
    p0: Array,
    bounds: dict[str, tuple[Bound, Bound]],
) -> tuple[Constraint, ...]:
    """Every rule of ``robot``, in a fixed order: the box ``bounds`` of the free variables, the
    rules between control points, then those on the trajectory sampled on ``t``."""
    return tuple(
        _box(bounds) + _relational(robot, p0) + _sampled(robot, limits, feasibility, t, p0)
    )


def _box(bounds: dict[str, tuple[Bound, Bound]]) -> list[Constraint]:
    """Each variable's box bounds as rules, under the kind of the rule that sets them."""
    out: list[Constraint] = []
    kind_of = {
        "P3": "shape",
        "P4": "shape",
        "P5": "transition",
        "P10": "transition",
        "P11": "shape",
        "P12": "shape",
    }
    for var, (lo, hi) in bounds.items():
        lo_kind = "min_detachment" if lo.rule in ("ld < P5x", "hd < P5z") else kind_of[var[:-1]]
        out.append(Constraint(lo_kind, lo.rule, _lower(var, lo.value), box=True))
        out.append(Constraint(kind_of[var[:-1]], hi.rule, _upper(var, hi.value), box=True))
    return out


def _relational(r: config.Robot, p0: Array) -> list[Constraint]:
    """Rules between control points: P5 before P10, the peel height, the detachment shape."""
    lf, hs = r.foot.pad_length, r.foot.droop_height
    out = [Constraint("transition", "P5x < P10x", lambda c: c["P5x"] - c["P10x"])]
    if r.shape.complete_detachment == "peel":

        def peel_height(c: Population) -> Array:
            arc = np.sqrt(np.maximum(0.0, lf**2 - (c["P10x"] - lf) ** 2))
            return np.maximum(hs, arc) - c["P10z"]

        out.append(
            Constraint("transition", "max(hs, sqrt(lf^2 - (P10x - lf)^2)) < P10z", peel_height)
        )
    if r.shape.detachment == "upper_triangle":

        def above_chord(p: str) -> Callable[[Population], Array]:
            def fn(c: Population) -> Array:
                slope = (c["P5z"] - p0[1]) / np.maximum(c["P5x"] - p0[0], 1e-12)
                return p0[1] + (c[p + "x"] - p0[0]) * slope - c[p + "z"]

            return fn

        out += [
            Constraint("shape", "P3x < P4x", lambda c: c["P3x"] - c["P4x"]),
            Constraint("shape", "P4x < P5x", lambda c: c["P4x"] - c["P5x"]),
            Constraint("shape", "P3z above chord P0-P5", above_chord("P3")),
            Constraint("shape", "P4z above chord P0-P5", above_chord("P4")),
            Constraint("shape", "P3z < P5z", lambda c: c["P3z"] - c["P5z"]),
            Constraint("shape", "P4z < P5z", lambda c: c["P4z"] - c["P5z"]),
        ]
    else:
        out += [
            Constraint("shape", "P3z < P4z (vertical lift)", lambda c: c["P3z"] - c["P4z"]),
            Constraint("shape", "P4z < P5z (vertical lift)", lambda c: c["P4z"] - c["P5z"]),
        ]
    return out


def _sampled(
    robot: config.Robot,
    limits: RobotLimits,
    feasibility: config.Feasibility,
    t: Array,
    p0: Array,
) -> list[Constraint]:
    """Rules on the trajectory sampled on the grid ``t``: the limits, the path's shape, then the
    leg's own joints."""
    rules = _limit_rules(robot, limits, feasibility, t, p0) + _path_rules(robot, feasibility, t)
    joints = Constraint(
        "joint_limit", "the leg's joints within range and speed", _joints(robot), True, last=True
    )
    return [Constraint(kind, name, fn, sampled=True) for kind, name, fn in rules] + [joints]


def _limit_rules(
    robot: config.Robot,
    limits: RobotLimits,
    feasibility: config.Feasibility,
    t: Array,
    p0: Array,
) -> list[Rule]:
    """Position (Ppl, P0x, the wall) and velocity (Vpl) limits on the sampled path."""
    pplx, pplz = limits.position
    vplx, vplz = limits.velocity
    tol = feasibility.position_tolerance
    floor = np.where(t > robot.timing.T2, -robot.shape.press_depth, p0[1])

    def extreme(key: str, axis: int, sign: float, limit: float) -> Callable[[Population], Array]:
        return lambda c: sign * c.extremes[key][:, axis] - limit

    return [
        ("position_limit", "trajectory x <= Pplx", extreme("position_max", 0, 1, pplx + tol)),
        ("position_limit", "trajectory z <= Pplz", extreme("position_max", 1, 1, pplz + tol)),
        (
            "position_limit",
            "trajectory x >= P0x",
            extreme("position_min", 0, -1, tol - p0[0]),
        ),
        (
            "position_limit",
            "trajectory z >= wall (or -press_depth while adhering)",
            lambda c: np.max(floor - c.samples.position[..., 1], axis=1) - tol,
        ),
        ("velocity_limit", "|vx| <= Vplx", extreme("speed_max", 0, 1, vplx)),
        ("velocity_limit", "|vz| <= Vplz", extreme("speed_max", 1, 1, vplz)),
    ]


def _joints(robot: config.Robot) -> Callable[[Population], Array]:
    """The leg's own joint ranges and speeds on the sampled path (:func:`joint_excess`): Ppl and
    Vpl bound the foot's box and speed but not every joint everywhere in it, and an optimum the
    search kept broke dq2 by 0.5 % in the controller export."""
    leg = build_leg(robot.leg)
    return lambda c: joint_excess(leg, c.samples.position, c.samples.velocity)


def _path_rules(robot: config.Robot, feasibility: config.Feasibility, t: Array) -> list[Rule]:
    """The bending guards (fs6, min_path_radius, no_cusp) and md on the path (``md_path``)."""
    tol = feasibility.position_tolerance
    r_min = robot.constraints.min_path_radius
    # a speed that moves the foot less than min_step in one grid interval has no direction
    min_speed = feasibility.min_step / float(t[1] - t[0])
    rules: list[Rule] = [
        (
            "bending",
            "fs6 = 0",
            lambda c: (
                fs6_bending(c.samples.position, feasibility.min_step) - feasibility.bend_tolerance
            ),
        ),
        (
            "bending",
            "min_path_radius",
            lambda c: path_radius_violation(
                c.samples.velocity, c.samples.acceleration, c.samples.t, r_min
            ),
        ),
        ("bending", "no_cusp", lambda c: reversal_violation(c.samples.velocity, min_speed)),
    ]
    if robot.constraints.md_path:
        md = robot.min_detachment
        rules.append(
            (
                "min_detachment",
                "md_path",
                lambda c: (
                    md_path_violation(
                        c.samples.position, c.samples.t, robot.timing.T1, md.ld, md.hd
                    )
                    - tol
                ),
            )
        )
    return rules


def _lower(var: str, value: float) -> Callable[[Population], Array]:
    return lambda c: value - c[var]


def _upper(var: str, value: float) -> Callable[[Population], Array]:
    return lambda c: c[var] - value
