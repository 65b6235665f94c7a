"""The foot-structure constraint policy (FTFOF §III.B, §VI.A).

Turns a robot preset plus its resolved limits into

- the free decision variables and their box (ties such as MST-Q's P10x = P11x = P12x and its
  vertical detachment P3x = P4x = P5x = P0x are removed by reparameterisation, never posed as
  equalities);
- a table of named constraints, each a vectorised violation measure (> 0 means violated) over a
  population of full 12-value decision vectors, covering the five constraint kinds of the paper
  plus the bending measure fs6. Swing containment is checked on the *sampled* trajectory (the
  published MST-M3F optimum has swing control points above Pplz while its curve stays below),
  and so are md on the path (``md_path``, switchable per robot) and the hairpin guards
  ``min_path_radius`` and ``no_cusp`` that keep fs6 from being passed between samples
  (:mod:`ftfof.trajectory.rules`).

An impossible description (a lower bound at or above its upper bound) raises
:class:`~ftfof.errors.InfeasibleRobotError` naming the constraint, before anything is sampled.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from ftfof import config
from ftfof.errors import InfeasibleRobotError
from ftfof.kinematics.limits import RobotLimits
from ftfof.objectives import fs6_bending
from ftfof.trajectory.bezier import DECISION_NAMES, Samples, evaluate
from ftfof.trajectory.rules import md_path_violation, path_radius_violation, reversal_violation

Array = NDArray[np.float64]
KINDS = (
    "position_limit",
    "velocity_limit",
    "min_detachment",
    "transition",
    "shape",
    "bending",
)
_COL = {name: i for i, name in enumerate(DECISION_NAMES)}


@dataclass(frozen=True)
class Constraint:
    """One named rule; ``violation`` maps the context to (pop,) amounts, > 0 = violated."""

    kind: str
    name: str
    violation: Callable[[_Context], Array]
    sampled: bool = False  # needs the sampled trajectory (costly) rather than control points
    box: bool = False  # a plain bound on one free variable (an optimiser's box enforces it)


@dataclass
class _Context:
    """A population under check: the decision columns and, lazily, its sampled trajectory."""

    X: Array
    sampler: Callable[[Array], Samples]
    _samples: Samples | None = field(default=None, repr=False)

    def __getitem__(self, name: str) -> Array:
        return self.X[:, _COL[name]]

    @property
    def samples(self) -> Samples:
        if self._samples is None:
            self._samples = self.sampler(self.X)
        return self._samples

    @cached_property
    def extremes(self) -> dict[str, Array]:
        """Per-row extremes of the sampled path, each (pop, 2): one pass shared by every rule."""
        pos, vel = self.samples.position, self.samples.velocity
        dims = range(pos.shape[-1])  # per component: each is contiguous in time

        def per_axis(reduce: Callable[[Array], Array], A: Array) -> Array:
            return np.column_stack([reduce(A[..., k]) for k in dims])

        return {
            "position_max": per_axis(lambda a: a.max(axis=-1), pos),
            "position_min": per_axis(lambda a: a.min(axis=-1), pos),
            "speed_max": per_axis(lambda a: np.maximum(a.max(axis=-1), -a.min(axis=-1)), vel),
        }


@dataclass(frozen=True)
class FeasibilityReport:
    """Which rows satisfy every constraint, and by how much each one is violated."""

    names: tuple[str, ...]
    kinds: tuple[str, ...]
    violations: Array  # (pop, n_constraints)

    @property
    def feasible(self) -> NDArray[np.bool_]:
        """Rows with no violation; a NaN (rule not evaluated) never counts as satisfied."""
        V = self.violations
        return ~np.any((V > 0) | np.isnan(V), axis=1)

    def failed(self, row: int) -> list[str]:
        """Human-readable 'kind: rule (by amount)' for each constraint row ``row`` violates."""
        v = self.violations[row]
        return [
            f"{k}: {n} (by {v[j]:.3g})"
            for j, (k, n) in enumerate(zip(self.kinds, self.names, strict=True))
            if v[j] > 0
        ]

    def rejected_by(self) -> dict[str, int]:
        """How many rows each constraint rejects (a row may count under several)."""
        counts = np.sum(self.violations > 0, axis=0)
        return {n: int(c) for n, c in zip(self.names, counts, strict=True)}

    def evaluated_by(self) -> dict[str, int]:
        """How many rows each constraint was evaluated on (:meth:`ConstraintPolicy.screen`
        leaves the sampled-trajectory rules NaN on rows the control-point rules reject)."""
        counts = np.sum(~np.isnan(self.violations), axis=0)
        return {n: int(c) for n, c in zip(self.names, counts, strict=True)}

    def passed_by(self) -> dict[str, int]:
        """How many rows each constraint was evaluated on and passed."""
        counts = np.sum(self.violations <= 0, axis=0)
        return {n: int(c) for n, c in zip(self.names, counts, strict=True)}

    def rejected_by_kind(self) -> dict[str, int]:
        out = {}
        for kind in KINDS:
            cols = [j for j, k in enumerate(self.kinds) if k == kind]
            if cols:
                out[kind] = int(np.sum(np.any(self.violations[:, cols] > 0, axis=1)))
        return out


@dataclass(frozen=True)
class Bound:
    value: float
    rule: str


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
        self.constraints: tuple[Constraint, ...] = self._constraints()

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
        cols = [_COL[n] for n in self.free_names]
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
            return X[:, _COL[name]]

        def put(name: str, lo: Array | float, hi: Array | float, root: bool = False) -> None:
            nonlocal weight
            lo = np.maximum(lo, box[name][0].value)
            span = np.minimum(hi, box[name][1].value) - lo
            w = np.sqrt(u[name]) if root else u[name]
            X[:, _COL[name]] = lo + w * span
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

    def _constraints(self) -> tuple[Constraint, ...]:
        r = self.robot
        out: list[Constraint] = []
        kind_of = {
            "P3": "shape",
            "P4": "shape",
            "P5": "transition",
            "P10": "transition",
            "P11": "shape",
            "P12": "shape",
        }
        for var, (lo, hi) in self.variable_bounds().items():
            lo_kind = "min_detachment" if lo.rule in ("ld < P5x", "hd < P5z") else kind_of[var[:-1]]
            out.append(Constraint(lo_kind, lo.rule, _lower(var, lo.value), box=True))
            out.append(Constraint(kind_of[var[:-1]], hi.rule, _upper(var, hi.value), box=True))
        out += self._relational(r)
        out += self._sampled()
        return tuple(out)

    def _relational(self, r: config.Robot) -> list[Constraint]:
        lf, hs = r.foot.pad_length, r.foot.droop_height
        out = [Constraint("transition", "P5x < P10x", lambda c: c["P5x"] - c["P10x"])]
        if r.shape.complete_detachment == "peel":

            def peel_height(c: _Context) -> Array:
                arc = np.sqrt(np.maximum(0.0, lf**2 - (c["P10x"] - lf) ** 2))
                return np.maximum(hs, arc) - c["P10z"]

            out.append(
                Constraint("transition", "max(hs, sqrt(lf^2 - (P10x - lf)^2)) < P10z", peel_height)
            )
        if r.shape.detachment == "upper_triangle":

            def above_chord(p: str) -> Callable[[_Context], Array]:
                def fn(c: _Context) -> Array:
                    slope = (c["P5z"] - self.p0[1]) / np.maximum(c["P5x"] - self.p0[0], 1e-12)
                    return self.p0[1] + (c[p + "x"] - self.p0[0]) * slope - c[p + "z"]

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

    def _sampled(self) -> list[Constraint]:
        pplx, pplz = self.limits.position
        vplx, vplz = self.limits.velocity
        tol = self.feasibility.position_tolerance
        floor = np.where(self.t > self.timing.T2, -self.robot.shape.press_depth, self.p0[1])
        r_min = self.robot.constraints.min_path_radius
        # a speed that moves the foot less than min_step in one grid interval has no direction
        min_speed = self.feasibility.min_step / float(self.t[1] - self.t[0])

        def extreme(key: str, axis: int, sign: float, limit: float) -> Callable[[_Context], Array]:
            return lambda c: sign * c.extremes[key][:, axis] - limit

        rules = [
            ("position_limit", "trajectory x <= Pplx", extreme("position_max", 0, 1, pplx + tol)),
            ("position_limit", "trajectory z <= Pplz", extreme("position_max", 1, 1, pplz + tol)),
            (
                "position_limit",
                "trajectory x >= P0x",
                extreme("position_min", 0, -1, tol - self.p0[0]),
            ),
            (
                "position_limit",
                "trajectory z >= wall (or -press_depth while adhering)",
                lambda c: np.max(floor - c.samples.position[..., 1], axis=1) - tol,
            ),
            ("velocity_limit", "|vx| <= Vplx", extreme("speed_max", 0, 1, vplx)),
            ("velocity_limit", "|vz| <= Vplz", extreme("speed_max", 1, 1, vplz)),
            (
                "bending",
                "fs6 = 0",
                lambda c: (
                    fs6_bending(c.samples.position, self.feasibility.min_step)
                    - self.feasibility.bend_tolerance
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
        if self.robot.constraints.md_path:
            md = self.robot.min_detachment
            rules.append(
                (
                    "min_detachment",
                    "md_path",
                    lambda c: (
                        md_path_violation(
                            c.samples.position, c.samples.t, self.timing.T1, md.ld, md.hd
                        )
                        - tol
                    ),
                )
            )
        return [Constraint(kind, name, fn, sampled=True) for kind, name, fn in rules]

    def check(
        self,
        X: Array,
        samples: Samples | None = None,
        constraints: tuple[Constraint, ...] | None = None,
    ) -> FeasibilityReport:
        """Every constraint (or the given ones) on every row of ``X`` (pop, 12).

        ``samples`` may pass the trajectory already sampled on the policy grid, saving a pass.
        """
        ctx = _Context(np.atleast_2d(np.asarray(X, dtype=float)), self.sample, samples)
        rules = self.constraints if constraints is None else constraints
        return _report(rules, np.column_stack([c.violation(ctx) for c in rules]))

    def screen(self, X: Array, chunk: int = 8192) -> FeasibilityReport:
        """Like :meth:`check`, but the sampled-trajectory rules run only on rows that pass the
        control-point rules (others get NaN there): cheap enough for millions of draws."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        ctx = _Context(X, self.sample)
        cheap = [j for j, c in enumerate(self.constraints) if not c.sampled]
        V = np.full((len(X), len(self.constraints)), np.nan)
        V[:, cheap] = np.column_stack([self.constraints[j].violation(ctx) for j in cheap])
        survivors = np.flatnonzero(~np.any(V[:, cheap] > 0, axis=1))
        costly = [j for j, c in enumerate(self.constraints) if c.sampled]
        for start in range(0, len(survivors), chunk):
            rows = survivors[start : start + chunk]
            sub = _Context(X[rows], self.sample)
            V[np.ix_(rows, costly)] = np.column_stack(
                [self.constraints[j].violation(sub) for j in costly]
            )
        return _report(self.constraints, V)


def _report(rules: tuple[Constraint, ...], V: Array) -> FeasibilityReport:
    return FeasibilityReport(tuple(c.name for c in rules), tuple(c.kind for c in rules), V)


def _lower(var: str, value: float) -> Callable[[_Context], Array]:
    return lambda c: value - c[var]


def _upper(var: str, value: float) -> Callable[[_Context], Array]:
    return lambda c: c[var] - value
