"""The foot-structure constraint policy (FTFOF §III.B, §VI.A).

Turns a robot preset plus its resolved limits into

- the free decision variables and their box (ties such as MST-Q's P10x = P11x = P12x and its
  vertical detachment P3x = P4x = P5x = P0x are removed by reparameterisation, never posed as
  equalities);
- the table of named constraints (:mod:`ftfof.trajectory.constraints`), run on populations of
  full 12-value decision vectors into a :class:`~ftfof.trajectory.feasibility.FeasibilityReport`.

An impossible description (a lower bound at or above its upper bound) raises
:class:`~ftfof.errors.InfeasibleRobotError` naming the constraint, before anything is sampled.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.errors import InfeasibleRobotError
from ftfof.kinematics.limits import RobotLimits
from ftfof.trajectory.bezier import DECISION_NAMES, Samples, evaluate
from ftfof.trajectory.constraints import constraint_table
from ftfof.trajectory.feasibility import (
    COLUMN,
    Bound,
    Constraint,
    FeasibilityReport,
    Population,
    report,
)
from ftfof.trajectory.piecewise import Sampled

Array = NDArray[np.float64]


class ConstraintPolicy:
    """Decision space and feasibility rules for one robot."""

    def __init__(
        self,
        robot: config.Robot,
        limits: RobotLimits,
        feasibility: config.Feasibility,
        name: str = "robot",
    ):
        self.robot = robot
        self.limits = limits
        self.feasibility = feasibility
        self.name = name
        self.p0 = np.zeros(2)
        self.p15 = np.array([robot.landing.x, robot.landing.z])
        self.timing = robot.timing
        self.t = robot.timing.grid(feasibility.n_t)
        self._fixed = self._fixed_values()
        self._follows = self._ties()
        self.free_names: tuple[str, ...] = tuple(
            n for n in DECISION_NAMES if n not in self._fixed and n not in self._follows
        )
        self.lower, self.upper = self._free_box()
        self._expand_A, self._expand_c = self._expansion()
        self.constraints: tuple[Constraint, ...] = constraint_table(
            robot, limits, feasibility, self.t, self.p0, self.variable_bounds()
        )

    # --- decision space -----------------------------------------------------------------------

    def _fixed_values(self) -> dict[str, float]:
        if self.robot.shape.detachment == "vertical":
            return {"P3x": self.p0[0], "P4x": self.p0[0], "P5x": self.p0[0]}
        return {}

    def _ties(self) -> dict[str, str]:
        if self.robot.shape.adhesion == "vertical_press":
            return {"P11x": "P10x", "P12x": "P10x"}
        return {}

    def variable_bounds(self) -> dict[str, tuple[Bound, Bound]]:
        """Box bounds of every non-fixed decision variable with the rule each comes from."""
        r, lim = self.robot, self.limits.position
        pplx, pplz = lim
        lf, hs = r.foot.pad_length, r.foot.droop_height
        md = r.min_detachment
        x0, z0 = self.p0
        b: dict[str, tuple[Bound, Bound]] = {}
        if r.shape.detachment == "upper_triangle":
            b["P3x"] = (Bound(x0, "P0x < P3x"), Bound(pplx, "P3x < Pplx"))
            b["P4x"] = (Bound(x0, "P0x < P4x"), Bound(pplx, "P4x < Pplx"))
            b["P5x"] = (Bound(md.ld, "ld < P5x"), Bound(pplx, "P5x < Pplx"))
        b["P3z"] = (Bound(z0, "P0z < P3z"), Bound(pplz, "P3z < Pplz"))
        b["P4z"] = (Bound(z0, "P0z < P4z"), Bound(pplz, "P4z < Pplz"))
        b["P5z"] = (Bound(md.hd, "hd < P5z"), Bound(pplz, "P5z < Pplz"))
        b["P10x"] = (Bound(max(lf, md.ld), "max(P5x, lf) < P10x"), Bound(pplx, "P10x < Pplx"))
        b["P10z"] = (Bound(hs, "hs < P10z"), Bound(pplz, "P10z < Pplz"))
        if r.shape.adhesion == "arc_from_right":
            for p in ("P11", "P12"):
                b[p + "x"] = (Bound(self.p15[0], f"P15x < {p}x"), Bound(pplx, f"{p}x < Pplx"))
                b[p + "z"] = (Bound(self.p15[1], f"P15z < {p}z"), Bound(pplz, f"{p}z < Pplz"))
        else:
            floor = -r.shape.press_depth
            for p in ("P11", "P12"):
                b[p + "z"] = (Bound(floor, f"-press_depth < {p}z"), Bound(pplz, f"{p}z < Pplz"))
        return b

    def _free_box(self) -> tuple[Array, Array]:
        bounds = self.variable_bounds()
        where = f"robots.{self.name}"
        if self.robot.shape.detachment == "vertical" and self.robot.min_detachment.ld != 0:
            raise InfeasibleRobotError(
                f"{where}.min_detachment.ld", "vertical detachment needs ld = 0 (P5x = P0x)"
            )
        for rule, lo, hi in self._landing_checks():
            if not lo < hi:
                raise InfeasibleRobotError(
                    f"{where}.landing", f"{rule} cannot hold ({lo:.4g} >= {hi:.4g} m)"
                )
        for var, (lo, hi) in bounds.items():
            if not lo.value < hi.value:
                raise InfeasibleRobotError(
                    where,
                    f"{var} has no room: {lo.rule} and {hi.rule} need "
                    f"{lo.value:.4g} < {hi.value:.4g} m",
                )
        lower = np.array([bounds[n][0].value for n in self.free_names])
        upper = np.array([bounds[n][1].value for n in self.free_names])
        return lower, upper

    def _landing_checks(self) -> list[tuple[str, float, float]]:
        """The landing point itself must lie inside the position limit box."""
        pplx, pplz = self.limits.position
        floor = -self.robot.shape.press_depth
        return [
            ("P0x < P15x < Pplx (landing beyond Ppl)", self.p15[0], pplx),
            ("P15z < Pplz (landing beyond Ppl)", self.p15[1], pplz),
            (
                "-press_depth <= P15z (landing deeper than the press depth)",
                floor,
                self.p15[1] + 1e-12,
            ),
        ]

    def _expansion(self) -> tuple[Array, Array]:
        A = np.zeros((len(DECISION_NAMES), len(self.free_names)))
        c = np.zeros(len(DECISION_NAMES))
        free_col = {n: j for j, n in enumerate(self.free_names)}
        for i, n in enumerate(DECISION_NAMES):
            if n in self._fixed:
                c[i] = self._fixed[n]
            else:
                A[i, free_col[self._follows.get(n, n)]] = 1.0
        return A, c

    def expand(self, free: Array) -> Array:
        """Free variables (pop, k) -> full decision vectors (pop, 12) in the paper's order."""
        return np.atleast_2d(free) @ self._expand_A.T + self._expand_c

    def contract(self, X: Array) -> Array:
        """Full decision vectors -> free variables (the tied copies must agree)."""
        cols = [COLUMN[n] for n in self.free_names]
        return np.atleast_2d(X)[:, cols]

    @property
    def n_free(self) -> int:
        return len(self.free_names)

    def shaped(self, U: Array) -> tuple[Array, Array]:
        """Unit-cube points (pop, n_free) -> full decision vectors inside the control-point rules,
        and each point's box weight.

        Why: the box holds the shape and transition rules as inequalities between variables, so
        most box draws (MST-M3F: > 99 %) break one of them before any trajectory is sampled. Each
        variable is instead drawn between bounds set by the variables drawn before it: P10x in its
        box; P5x below P10x; (P3x, P4x) uniform over the ordered triangle below P5x (the square
        root keeps that pair uniform); P3z, P4z between the chord P0-P5 and P5z (a vertical lift:
        ordered below P5z like the x pair); P10z above the peel height; the rest in their box.
        The map is onto the region the control-point rules allow (up to its boundary), so no
        feasible trajectory is out of reach; it is not volume-preserving, so a uniform design is
        not uniform over that region. It restates those rules rather than replaces them: callers
        still :meth:`check` every rule on what it returns.

        The weight is the map's Jacobian over the box volume: its mean over a uniform design
        estimates the fraction of the box the control-point rules keep, and its mean times
        feasibility the fraction of the box that is feasible (what plain box draws would accept).
        """
        U = np.atleast_2d(U)
        box = self.variable_bounds()
        u = {n: U[:, j] for j, n in enumerate(self.free_names)}
        X = self.expand(np.zeros_like(U))
        weight = np.full(len(U), 1.0 / float(np.prod(self.upper - self.lower)))

        def col(name: str) -> Array:
            return X[:, COLUMN[name]]

        def put(name: str, lo: Array | float, hi: Array | float, root: bool = False) -> None:
            nonlocal weight
            lo = np.maximum(lo, box[name][0].value)
            span = np.minimum(hi, box[name][1].value) - lo
            w = np.sqrt(u[name]) if root else u[name]
            X[:, COLUMN[name]] = lo + w * span
            # d sqrt(u) / du = 1 / (2 sqrt(u)); the next variable's span (w * span) cancels it
            weight = weight * span * (0.5 / np.maximum(w, 1e-300) if root else 1.0)

        r = self.robot
        lf = r.foot.pad_length
        done = {"P3x", "P4x", "P5x", "P10x", "P3z", "P4z", "P5z"}
        put("P10x", -np.inf, np.inf)
        triangle = r.shape.detachment == "upper_triangle"
        if triangle:
            put("P5x", -np.inf, col("P10x"))
            put("P4x", self.p0[0], col("P5x"), root=True)
            put("P3x", self.p0[0], col("P4x"))
        put("P5z", -np.inf, np.inf)
        if triangle:
            slope = (col("P5z") - self.p0[1]) / np.maximum(col("P5x") - self.p0[0], 1e-12)
            for p in ("P3", "P4"):
                put(p + "z", self.p0[1] + (col(p + "x") - self.p0[0]) * slope, col("P5z"))
        else:
            put("P4z", -np.inf, col("P5z"), root=True)
            put("P3z", -np.inf, col("P4z"))
        if r.shape.complete_detachment == "peel":
            put("P10z", np.sqrt(np.maximum(0.0, lf**2 - (col("P10x") - lf) ** 2)), np.inf)
            done.add("P10z")
        for name in self.free_names:
            if name not in done:
                put(name, -np.inf, np.inf)
        return self.expand(self.contract(X)), weight

    def at_rate(self, hz: float) -> ConstraintPolicy:
        """The same rules on a grid at least ``hz`` samples per second over [0, T3].

        Why: a rule met on the policy's n_t samples can fail between them (MST-M3F at 256
        samples: 5 % of accepted draws broke md_path at 1 kHz), and a controller replays the
        trajectory at its own rate.
        """
        n_t = max(self.feasibility.n_t, math.ceil(self.timing.T3 * hz) + 1)
        feasibility = self.feasibility.model_copy(update={"n_t": n_t})
        return ConstraintPolicy(self.robot, self.limits, feasibility, self.name)

    # --- trajectories -------------------------------------------------------------------------

    def sample(self, X: Array, t: Array | None = None) -> Samples:
        """Position/velocity/acceleration of full decision vectors on the check grid (or ``t``)."""
        return evaluate(X, self.p0, self.p15, self.timing, self.t if t is None else t)

    # --- constraints --------------------------------------------------------------------------

    def check(
        self,
        X: Array,
        samples: Samples | None = None,
        constraints: tuple[Constraint, ...] | None = None,
    ) -> FeasibilityReport:
        """Every constraint (or the given ones) on every row of ``X`` (pop, 12).

        ``samples`` may pass the trajectory already sampled on the policy grid, saving a pass.
        """
        ctx = Population(np.atleast_2d(np.asarray(X, dtype=float)), self.sample, samples)
        rules = self.constraints if constraints is None else constraints
        return report(rules, np.column_stack([c.violation(ctx) for c in rules]))

    def path_failures(self, trajectory: Sampled) -> list[str]:
        """The rules on the sampled path (reach, speed, the wall, md_path, bends) that
        ``trajectory`` breaks on the policy grid: how a trajectory that is not a Bezier row of
        this robot (a common baseline) is judged."""
        rules = tuple(c for c in self.constraints if c.sampled)
        samples = trajectory.sample(self.t)
        X = np.zeros((1, len(DECISION_NAMES)))  # no control points: only path rules run
        return self.check(X, samples=samples, constraints=rules).failed(0)

    def screen(self, X: Array, chunk: int = 8192) -> FeasibilityReport:
        """Like :meth:`check`, but the sampled-trajectory rules run only on rows that pass the
        control-point rules (others get NaN there): cheap enough for millions of draws."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        ctx = Population(X, self.sample)
        cheap = [j for j, c in enumerate(self.constraints) if not c.sampled]
        V = np.full((len(X), len(self.constraints)), np.nan)
        V[:, cheap] = np.column_stack([self.constraints[j].violation(ctx) for j in cheap])
        survivors = np.flatnonzero(~np.any(V[:, cheap] > 0, axis=1))
        costly = [j for j, c in enumerate(self.constraints) if c.sampled]
        for start in range(0, len(survivors), chunk):
            rows = survivors[start : start + chunk]
            sub = Population(X[rows], self.sample)
            V[np.ix_(rows, costly)] = np.column_stack(
                [self.constraints[j].violation(sub) for j in costly]
            )
        return report(self.constraints, V)
