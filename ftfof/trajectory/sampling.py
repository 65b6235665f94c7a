"""Sampling the climbable set (FTFOF §VI.B; docs/pipeline.md).

Draws a seeded scrambled-Sobol (or Latin hypercube) design in the unit cube in batches, maps it
onto the region the control-point rules allow (:meth:`ConstraintPolicy.shaped`), keeps the rows
that pass every rule in draw order, and stops at ``n`` or, with a clear error, when the draw
budget is spent. Why the map: the shape and transition rules are inequalities between variables
that reject > 99 % of plain box draws for MST-M3F, and the whole-path rules leave ~1e-5 of the box,
so box draws needed ~6e7 draws for n = 1000; the map costs one sampled-trajectory check per draw
and accepts ~1 %. The acceptance test is unchanged: every batch is screened vectorised with every
rule (the control-point rules on all draws, the sampled-trajectory rules on the draws that pass
them), and the rows that pass are checked again on a grid at ``feasibility.recheck_hz`` (1 kHz),
since a rule met on n_t samples can fail between them. Rows are spread by the map, not uniform
over the feasible set; the box weights of the map still give what plain box draws would accept.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.stats import qmc

from ftfof.config import Design
from ftfof.errors import SamplingError
from ftfof.trajectory.feasibility import FeasibilityReport
from ftfof.trajectory.policy import ConstraintPolicy

Array = NDArray[np.float64]


@dataclass(frozen=True)
class SampleResult:
    X: Array  # (n, 12) full decision vectors, feasible
    draws: int  # mapped design points drawn
    accepted: int  # draws that passed every rule on both grids (>= n: the last batch may overrun)
    rejected_by_fine_recheck: int  # draws that passed on the n_t grid and failed at recheck_hz
    box_acceptance: float  # estimated fraction of the free-variable box that is feasible
    rejected_by: dict[str, int]
    rejected_by_kind: dict[str, int]
    evaluated_by: dict[str, int]  # draws each rule ran on (sampled rules: control-point survivors)
    passed_by: dict[str, int]

    @property
    def pass_fraction(self) -> dict[str, float]:
        """Per rule, the fraction of the draws it ran on that pass it."""
        return {n: self.passed_by[n] / c if c else 0.0 for n, c in self.evaluated_by.items()}

    @property
    def acceptance_rate(self) -> float:
        """Per mapped draw (what this sampler pays), not per box draw: see ``box_acceptance``."""
        return self.accepted / self.draws if self.draws else 0.0


def _design(kind: Design, d: int, seed: int) -> Callable[[int], Array]:
    engine: qmc.QMCEngine
    if kind == "sobol":
        engine = qmc.Sobol(d, scramble=True, rng=np.random.default_rng(seed))
    else:
        engine = qmc.LatinHypercube(d, rng=np.random.default_rng(seed))
    return engine.random


def _batch_sizes(batch: int, max_draws: int) -> Iterator[int]:
    """Equal power-of-two batches: each is a balanced block of the Sobol sequence."""
    size = 1 << max(4, int(np.ceil(np.log2(batch))))
    total = 0
    while total < max_draws:
        yield min(size, max_draws - total)
        total += size


@dataclass
class _Tally:
    """Per-rule counts summed over the batches (:class:`SampleResult`'s)."""

    rejected: dict[str, int] = field(default_factory=dict)
    rejected_kind: dict[str, int] = field(default_factory=dict)
    evaluated: dict[str, int] = field(default_factory=dict)
    passed: dict[str, int] = field(default_factory=dict)

    def add(self, report: FeasibilityReport) -> None:
        for into, counts in (
            (self.rejected, report.rejected_by()),
            (self.rejected_kind, report.rejected_by_kind()),
            (self.evaluated, report.evaluated_by()),
            (self.passed, report.passed_by()),
        ):
            for name, count in counts.items():
                into[name] = into.get(name, 0) + count


def sample_feasible(
    policy: ConstraintPolicy,
    n: int,
    seed: int,
    design: Design = "sobol",
    batch: int = 4096,
    max_draws: int = 4_000_000,
    progress: Callable[[int, int], None] | None = None,
) -> SampleResult:
    """``n`` feasible trajectories, deterministic for a seed.

    ``progress(accepted, draws)`` is called after every batch.
    """
    draw = _design(design, policy.n_free, seed)
    fine = policy.at_rate(policy.feasibility.recheck_hz)
    kept: list[Array] = []
    accepted = draws = refused = 0
    box_hits = 0.0
    tally = _Tally()
    for size in _batch_sizes(batch, max_draws):
        if accepted >= n:
            break
        X, weight = policy.shaped(draw(size))
        report = policy.screen(X)
        tally.add(report)
        rows = np.flatnonzero(report.feasible)
        rows = rows[fine.screen(X[rows], chunk=1024).feasible]
        refused += int(report.feasible.sum()) - len(rows)
        box_hits += float(weight[rows].sum())
        kept.append(X[rows])
        accepted += len(rows)
        draws += len(X)
        if progress is not None:
            progress(min(accepted, n), draws)
    if accepted < n:
        raise SamplingError(
            "sample",
            f"only {accepted} of {n} feasible trajectories in {draws} draws "
            f"(acceptance {accepted / max(draws, 1):.2e}); raise sample.max_draws or relax the "
            f"robot's constraints (most rejections: {_top(tally.rejected)})",
        )
    return SampleResult(
        np.concatenate(kept)[:n],
        draws,
        accepted,
        refused,
        box_hits / draws,
        tally.rejected,
        tally.rejected_kind,
        tally.evaluated,
        tally.passed,
    )


def _top(counts: dict[str, int], k: int = 3) -> str:
    top = sorted(counts.items(), key=lambda kv: -kv[1])[:k]
    return ", ".join(f"{name} ({c})" for name, c in top) or "none"
