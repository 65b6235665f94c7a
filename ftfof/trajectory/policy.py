"""The foot-structure constraint policy (FTFOF §III.B, §VI.A).

Turns a robot preset plus its resolved limits into

- the free decision variables and their box (:mod:`ftfof.trajectory.decision`);
- the table of named constraints (:mod:`ftfof.trajectory.constraints`), run on populations of
  full 12-value decision vectors into a :class:`~ftfof.trajectory.feasibility.FeasibilityReport`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.kinematics.limits import RobotLimits
from ftfof.trajectory.bezier import DECISION_NAMES, Samples, evaluate
from ftfof.trajectory.constraints import constraint_table
from ftfof.trajectory.decision import DecisionSpace
from ftfof.trajectory.feasibility import Constraint, FeasibilityReport, Population, report
from ftfof.trajectory.piecewise import Sampled

Array = NDArray[np.float64]


class ConstraintPolicy(DecisionSpace):
    """Decision space (:class:`~ftfof.trajectory.decision.DecisionSpace`) and feasibility rules
    for one robot."""

    def __init__(
        self,
        robot: config.Robot,
        limits: RobotLimits,
        feasibility: config.Feasibility,
        name: str = "robot",
    ):
        super().__init__(robot, limits, name)
        self.feasibility = feasibility
        self.timing = robot.timing
        self.t = robot.timing.grid(feasibility.n_t)
        self.constraints: tuple[Constraint, ...] = constraint_table(
            robot, limits, feasibility, self.t, self.p0, self.variable_bounds()
        )

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
        control-point rules, and the ``last`` rules only on rows every other rule passes
        (others get NaN there): cheap enough for millions of draws."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        ctx = Population(X, self.sample)
        cheap = [j for j, c in enumerate(self.constraints) if not c.sampled]
        V = np.full((len(X), len(self.constraints)), np.nan)
        V[:, cheap] = np.column_stack([self.constraints[j].violation(ctx) for j in cheap])
        survivors = np.flatnonzero(~np.any(V[:, cheap] > 0, axis=1))
        costly = [j for j, c in enumerate(self.constraints) if c.sampled and not c.last]
        last = [j for j, c in enumerate(self.constraints) if c.last]
        for start in range(0, len(survivors), chunk):
            rows = survivors[start : start + chunk]
            sub = Population(X[rows], self.sample)
            V[np.ix_(rows, costly)] = np.column_stack(
                [self.constraints[j].violation(sub) for j in costly]
            )
            rows = rows[~np.any(V[np.ix_(rows, costly)] > 0, axis=1)]
            if last and len(rows):
                sub = Population(X[rows], self.sample)
                V[np.ix_(rows, last)] = np.column_stack(
                    [self.constraints[j].violation(sub) for j in last]
                )
        return report(self.constraints, V)
