"""What a feasibility check is made of: named constraints, the population they measure, the
report they return (:class:`~ftfof.trajectory.policy.ConstraintPolicy` builds and runs them)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from ftfof.trajectory.bezier import DECISION_NAMES, Samples

Array = NDArray[np.float64]
# the five constraint kinds of the paper, the leg's own joint limits, and the bending measure fs6
KINDS = (
    "position_limit",
    "velocity_limit",
    "joint_limit",
    "min_detachment",
    "transition",
    "shape",
    "bending",
)
COLUMN = {name: i for i, name in enumerate(DECISION_NAMES)}  # in a full decision vector


@dataclass(frozen=True)
class Bound:
    """A bound on one decision variable, with the rule it comes from (for messages)."""

    value: float
    rule: str


@dataclass(frozen=True)
class Constraint:
    """One named rule; ``violation`` maps a population to (pop,) amounts, > 0 = violated."""

    kind: str
    name: str
    violation: Callable[[Population], Array]
    sampled: bool = False  # needs the sampled trajectory (costly) rather than control points
    box: bool = False  # a plain bound on one free variable (an optimiser's box enforces it)
    last: bool = False  # costlier than the rest and seldom decisive: a screen runs it only on
    # rows every other rule passes


@dataclass
class Population:
    """A population under check: the decision columns and, lazily, its sampled trajectory."""

    X: Array
    sampler: Callable[[Array], Samples]
    _samples: Samples | None = field(default=None, repr=False)

    def __getitem__(self, name: str) -> Array:
        return self.X[:, COLUMN[name]]

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
        """How many rows each constraint was evaluated on (:meth:`~ftfof.trajectory.policy.
        ConstraintPolicy.screen` leaves the sampled-trajectory rules NaN on rows the
        control-point rules reject)."""
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


def report(rules: tuple[Constraint, ...], V: Array) -> FeasibilityReport:
    """The report of ``rules`` from their violations ``V`` (pop, len(rules))."""
    return FeasibilityReport(tuple(c.name for c in rules), tuple(c.kind for c in rules), V)
