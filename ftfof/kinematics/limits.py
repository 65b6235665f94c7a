"""Maximum foot position Ppl and velocity Vpl from the leg model (FTFOF eq. 7-8).

Both are bi-objective NSGA-II searches (maximise the x and z components) over the leg's free
sagittal joints, with the dependent joint kept inside its range and the paper's condition z <= x
("move far rather than lift high"). The paper does not say which Pareto point it keeps; we keep
the one with the largest product x*z, i.e. the largest box [P0, Ppl] whose far corner the leg can
still reach, which is exactly how Ppl is used afterwards (a box bound). Vpl likewise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pymoo.algorithms.moo.nsga2 import NSGA2
from pymoo.core.problem import Problem
from pymoo.optimize import minimize

import ftfof.config as config
from ftfof.errors import InfeasibleRobotError
from ftfof.kinematics.legs import Array, Leg, build_leg, within_limits

SEARCH_POP = 100
SEARCH_GENERATIONS = 150


@dataclass(frozen=True)
class ReachResult:
    """One leg limit: the raw extreme, its joint state and the value after the safety factor."""

    raw: Array  # (2,) x, z
    theta: Array  # (3,) joint angles at the extreme
    theta_dot: Array | None  # (3,) joint rates, velocity search only
    safety_factor: float

    @property
    def value(self) -> Array:
        return self.raw * self.safety_factor


def _dependent_violation(leg: Leg, theta: Array) -> Array:
    """How far the dependent joint lies outside its range (>0 infeasible), NaN -> large."""
    j = ({0, 1, 2} - set(leg.free_joints)).pop()
    lo, hi = leg.joint_limits[j]
    v = np.maximum(lo - theta[..., j], theta[..., j] - hi)
    return np.where(np.isfinite(v), v, 1e3)


class _PositionReach(Problem):
    def __init__(self, leg: Leg):
        self.leg = leg
        lim = leg.joint_limits[list(leg.free_joints)]
        super().__init__(n_var=2, n_obj=2, n_ieq_constr=2, xl=lim[:, 0], xu=lim[:, 1])

    def _evaluate(self, X, out, *args, **kwargs):
        theta = self.leg.sagittal_angles(X)
        p = np.nan_to_num(self.leg.forward(theta), nan=-1.0)
        out["F"] = -p
        out["G"] = np.column_stack([p[:, 1] - p[:, 0], _dependent_violation(self.leg, theta)])


class _VelocityReach(Problem):
    def __init__(self, leg: Leg):
        self.leg = leg
        free = list(leg.free_joints)
        lim = leg.joint_limits[free]
        speed = leg.speed_limits[free]
        xl = np.concatenate([lim[:, 0], -speed])
        xu = np.concatenate([lim[:, 1], speed])
        super().__init__(n_var=4, n_obj=2, n_ieq_constr=3, xl=xl, xu=xu)

    def _evaluate(self, X, out, *args, **kwargs):
        theta = self.leg.sagittal_angles(X[:, :2])
        rates = self.leg.sagittal_rates(theta, X[:, 2:])
        p = np.nan_to_num(self.leg.forward(theta), nan=-1.0)
        v = np.nan_to_num(np.einsum("pij,pj->pi", self.leg.jacobian(theta), rates), nan=-1.0)
        j = ({0, 1, 2} - set(self.leg.free_joints)).pop()
        rate_excess = np.abs(rates[:, j]) - self.leg.speed_limits[j]
        out["F"] = -v
        out["G"] = np.column_stack(
            [
                p[:, 1] - p[:, 0],
                _dependent_violation(self.leg, theta),
                np.where(np.isfinite(rate_excess), rate_excess, 1e3),
            ]
        )


def _largest_box(F: Array, G: Array) -> int:
    """Index of the feasible Pareto point with both components positive and the largest x*z."""
    value = -F
    ok = np.all(G <= 0, axis=1) & np.all(value > 0, axis=1)
    if not ok.any():
        raise ValueError("no reachable point with x > 0 and z > 0 satisfies z <= x")
    area = np.where(ok, value[:, 0] * value[:, 1], -np.inf)
    return int(np.argmax(area))


def _solve(problem: Problem, seed: int) -> tuple[Array, Array]:
    """NSGA-II on a reach problem, then the point it keeps (:func:`_largest_box`): that point's
    decision vector and its (x, z) extreme."""
    res = minimize(problem, NSGA2(pop_size=SEARCH_POP), ("n_gen", SEARCH_GENERATIONS), seed=seed)
    pop = res.pop
    i = _largest_box(pop.get("F"), pop.get("G"))
    return pop.get("X")[i], -pop.get("F")[i]


def position_reach(leg: Leg, safety_factor: float, seed: int = 0) -> ReachResult:
    """Ppl by eq. 7."""
    X, raw = _solve(_PositionReach(leg), seed)
    return ReachResult(raw, leg.sagittal_angles(X), None, safety_factor)


def velocity_reach(leg: Leg, safety_factor: float, seed: int = 0) -> ReachResult:
    """Vpl by eq. 8: v = J(theta) theta_dot within joint angle and rate limits."""
    X, raw = _solve(_VelocityReach(leg), seed)
    theta = leg.sagittal_angles(X[:2])
    return ReachResult(raw, theta, leg.sagittal_rates(theta, X[2:]), safety_factor)


@dataclass(frozen=True)
class RobotLimits:
    """The position and velocity limits the constraint policy uses, with where they came from."""

    position: Array  # Ppl (x, z), after the safety factor
    velocity: Array  # Vpl (x, z), after the safety factor
    position_source: str  # "pinned" or "derived"
    velocity_source: str
    position_reach: ReachResult | None = None
    velocity_reach: ReachResult | None = None

    def summary(self) -> dict[str, object]:
        out: dict[str, object] = {
            "Ppl": self.position.tolist(),
            "Vpl": self.velocity.tolist(),
            "Ppl_source": self.position_source,
            "Vpl_source": self.velocity_source,
        }
        for key, reach in (("Ppl", self.position_reach), ("Vpl", self.velocity_reach)):
            if reach is not None:
                out[f"{key}_raw"] = reach.raw.tolist()
                out[f"{key}_theta"] = reach.theta.tolist()
        return out


def resolve_limits(robot: config.Robot, name: str, seed: int = 0) -> RobotLimits:
    """Ppl and Vpl for a preset: pinned values are checked against the leg, others derived."""
    leg = build_leg(robot.leg)
    where = f"robots.{name}"
    pos = robot.position_limit
    if pos.pinned is not None:
        ppl = np.array([pos.pinned.x, pos.pinned.z])
        raw = ppl / pos.safety_factor
        theta = leg.inverse(raw)
        if not (np.all(np.isfinite(theta)) and within_limits(theta, leg.joint_limits)):
            raise InfeasibleRobotError(
                f"{where}.position_limit.pinned",
                f"Ppl / safety_factor = ({raw[0]:.4g}, {raw[1]:.4g}) m is outside the leg's "
                "reach within its joint limits",
            )
        p_reach = None
    else:
        p_reach = _search(position_reach, leg, pos.safety_factor, seed, f"{where}.position_limit")
        ppl = p_reach.value
    vel = robot.velocity_limit
    if vel.pinned is not None:
        vpl, v_reach = np.array([vel.pinned.x, vel.pinned.z]), None
    else:
        v_reach = _search(velocity_reach, leg, vel.safety_factor, seed, f"{where}.velocity_limit")
        vpl = v_reach.value
    return RobotLimits(
        ppl,
        vpl,
        "pinned" if p_reach is None else "derived",
        "pinned" if v_reach is None else "derived",
        p_reach,
        v_reach,
    )


def _search(fn, leg: Leg, safety: float, seed: int, where: str) -> ReachResult:
    try:
        return fn(leg, safety, seed)
    except ValueError as err:
        raise InfeasibleRobotError(where, str(err)) from err
