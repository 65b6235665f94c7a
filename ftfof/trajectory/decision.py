"""The decision space of one robot's trajectories (FTFOF §III.B, §VI.A): which of the 12 control
values are free, their box, and the map of the unit cube onto the region the control-point rules
allow (:meth:`DecisionSpace.shaped`).

Ties such as MST-Q's P10x = P11x = P12x and its vertical detachment P3x = P4x = P5x = P0x are
removed by reparameterisation, never posed as equalities. An impossible description (a lower bound
at or above its upper bound) raises :class:`~ftfof.errors.InfeasibleRobotError` naming the
constraint, before anything is sampled.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.errors import InfeasibleRobotError
from ftfof.kinematics.limits import RobotLimits
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.feasibility import COLUMN, Bound

Array = NDArray[np.float64]


class DecisionSpace:
    """The free decision variables of one robot, their box, and the maps to and from the full
    12-value decision vectors."""

    def __init__(self, robot: config.Robot, limits: RobotLimits, name: str = "robot"):
        self.robot = robot
        self.limits = limits
        self.name = name
        self.p0 = np.zeros(2)
        self.p15 = np.array([robot.landing.x, robot.landing.z])
        self._fixed = self._fixed_values()
        self._follows = self._ties()
        self.free_names: tuple[str, ...] = tuple(
            n for n in DECISION_NAMES if n not in self._fixed and n not in self._follows
        )
        self.lower, self.upper = self._free_box()
        self._expand_A, self._expand_c = self._expansion()

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
        still :meth:`~ftfof.trajectory.policy.ConstraintPolicy.check` every rule on what it returns.

        The weight is the map's Jacobian over the box volume: its mean over a uniform design
        estimates the fraction of the box the control-point rules keep, and its mean times
        feasibility the fraction of the box that is feasible (what plain box draws would accept).
        """
        return _shaped(self, U)


class _Draw:
    """The decision vectors the map has drawn so far, and their box weight: each variable drawn
    between bounds set by those drawn before it, within its box."""

    def __init__(self, space: DecisionSpace, U: Array):
        self.box = space.variable_bounds()
        self.u = {n: U[:, j] for j, n in enumerate(space.free_names)}
        self.X = space.expand(np.zeros_like(U))
        self.weight = np.full(len(U), 1.0 / float(np.prod(space.upper - space.lower)))

    def col(self, name: str) -> Array:
        return self.X[:, COLUMN[name]]

    def put(self, name: str, lo: Array | float, hi: Array | float, root: bool = False) -> None:
        box = self.box
        lo = np.maximum(lo, box[name][0].value)
        span = np.minimum(hi, box[name][1].value) - lo
        w = np.sqrt(self.u[name]) if root else self.u[name]
        self.X[:, COLUMN[name]] = lo + w * span
        # d sqrt(u) / du = 1 / (2 sqrt(u)); the next variable's span (w * span) cancels it
        self.weight = self.weight * span * (0.5 / np.maximum(w, 1e-300) if root else 1.0)


def _shaped(space: DecisionSpace, U: Array) -> tuple[Array, Array]:
    """The map of :meth:`DecisionSpace.shaped`, variable by variable."""
    U = np.atleast_2d(U)
    d = _Draw(space, U)
    r, p0 = space.robot, space.p0
    lf = r.foot.pad_length
    done = {"P3x", "P4x", "P5x", "P10x", "P3z", "P4z", "P5z"}
    d.put("P10x", -np.inf, np.inf)
    triangle = r.shape.detachment == "upper_triangle"
    if triangle:
        d.put("P5x", -np.inf, d.col("P10x"))
        d.put("P4x", p0[0], d.col("P5x"), root=True)
        d.put("P3x", p0[0], d.col("P4x"))
    d.put("P5z", -np.inf, np.inf)
    if triangle:
        slope = (d.col("P5z") - p0[1]) / np.maximum(d.col("P5x") - p0[0], 1e-12)
        for p in ("P3", "P4"):
            d.put(p + "z", p0[1] + (d.col(p + "x") - p0[0]) * slope, d.col("P5z"))
    else:
        d.put("P4z", -np.inf, d.col("P5z"), root=True)
        d.put("P3z", -np.inf, d.col("P4z"))
    if r.shape.complete_detachment == "peel":
        d.put("P10z", np.sqrt(np.maximum(0.0, lf**2 - (d.col("P10x") - lf) ** 2)), np.inf)
        done.add("P10z")
    for name in space.free_names:
        if name not in done:
            d.put(name, -np.inf, np.inf)
    return space.expand(space.contract(d.X)), d.weight
