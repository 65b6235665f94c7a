"""Does the answer hold at a finer solver step? Table I's trajectories simulated again with
every solver step set to ``evaluate.check_step``, side by side with the acquisition's runs.

The acquisition's step sets how finely the pad's sudden release is resolved: the body's peak
acceleration (fsj), the pull's second derivative (fs7) and the peak pull itself move with it, and
the optimiser only ever saw the acquisition's step. A change of step size within a run of the
generalized-alpha solver disturbs the body (docs/simulator.md, "Time step"), so the check runs at
one step throughout. This module puts the Table I figures the objectives read at both steps,
and how much of the optimum's change against the reference the finer step keeps.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ftfof.data import targets
from ftfof.evaluate.table import Column, TableRow, table_one

FINE = "fine:"  # source prefix of the runs at the check step
CHECKED: tuple[Column, ...] = (
    ("peak_pull", "max pull (resultant)", "N"),
    ("jitter", "body jitter in detachment", "m/s²"),
    ("force_jitter", "force jitter (fs7's total)", ""),
    ("landing_pre_pressure", "landing pre-pressure", "N"),
)
# the figures where lower is better, so that a change's shift reads as advantage lost or gained
# (the landing press is scored by its distance from a, not by its size)
LOWER_IS_BETTER = ("peak_pull", "jitter", "force_jitter")


def checked_figures(
    channels: Mapping[str, np.ndarray], scalars: Mapping[str, Any], T3: float
) -> dict[str, float]:
    """One run's CHECKED figures: the scalars, and the detachment-window maxima of the body's
    acceleration and of eq. 16's running total."""
    series = targets.full_rate(channels, T3)
    return {
        "peak_pull": float(scalars["peak_pull"]),
        "jitter": float(np.max(series["body_acc"])),
        "force_jitter": float(np.max(series["jitter"])),
        "landing_pre_pressure": float(scalars["landing_pre_pressure"]),
    }


@dataclass(frozen=True)
class StepCheck:
    """CHECKED at the acquisition ``step`` and at ``check_step``, each against the reference,
    over the trajectories simulated at both; ``missing`` names those that were not."""

    step: float
    check_step: float
    at_step: list[TableRow]
    at_check: list[TableRow]
    missing: list[str] = field(default_factory=list)

    def shift(self, trajectory: str) -> dict[str, float]:
        """Per LOWER_IS_BETTER figure, how many points of % change against the reference
        ``trajectory`` loses (> 0) or gains (< 0) at the check step; empty when it was not
        simulated at both."""
        before = {r.trajectory: r.change for r in self.at_step}.get(trajectory)
        after = {r.trajectory: r.change for r in self.at_check}.get(trajectory)
        if before is None or after is None:
            return {}
        return {c: after[c] - before[c] for c in LOWER_IS_BETTER}

    def as_dict(self, trajectory: str) -> dict:
        """For metrics.json: each trajectory's values and changes as [step, check step], and
        ``trajectory``'s shift."""
        fine = {r.trajectory: r for r in self.at_check}

        def pair(row: TableRow, part: str, column: str) -> list[float]:
            digits = 2 if part == "change" else 4
            values = (getattr(row, part)[column], getattr(fine[row.trajectory], part)[column])
            return [round(v, digits) for v in values]

        table = {
            r.trajectory: {
                **{c: pair(r, "values", c) for c, _, _ in CHECKED},
                **{f"{c}_change": pair(r, "change", c) for c, _, _ in CHECKED},
            }
            for r in self.at_step
        }
        return {
            "step": self.step,
            "check_step": self.check_step,
            "table": table,
            "shift": {c: round(v, 2) for c, v in self.shift(trajectory).items()},
            "missing": self.missing,
        }


def step_check(
    at_step: Mapping[str, dict],
    at_check: Mapping[str, dict],
    reference: str,
    step: float,
    check_step: float,
) -> StepCheck:
    """``at_step`` and ``at_check``: CHECKED figures by trajectory (the successful runs). The
    trajectories simulated at both are compared, in ``at_step``'s order; without the reference
    at both there is nothing to compare against, and the tables are empty."""
    both = [name for name in at_step if name in at_check]
    missing = sorted(set(at_step) ^ set(at_check))
    if reference not in both:
        return StepCheck(step, check_step, [], [], missing)
    return StepCheck(
        step,
        check_step,
        table_one({n: at_step[n] for n in both}, reference, CHECKED),
        table_one({n: at_check[n] for n in both}, reference, CHECKED),
        missing,
    )
