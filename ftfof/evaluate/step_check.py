"""Does the answer hold at a finer solver step? Table I's trajectories simulated again with
``evaluate.check_step``, side by side with the acquisition step's runs.

The solver's step while bonds break sets how much of the detachment's snap the body sees: the
body's peak acceleration (fsj) and the pull's second derivative (fs7) grow as the step shrinks,
and the optimiser, which only ever saw the acquisition step, may have found trajectories whose
advantage is numerical (docs/simulator.md, "Time step"). The pull and the landing press hardly
move. This module puts the Table I figures the objectives read at both steps, and the optimum's
change against the reference at each.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
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
    """CHECKED at the acquisition ``step`` and at ``check_step``, each against the reference."""

    step: float
    check_step: float
    at_step: list[TableRow]
    at_check: list[TableRow]

    def shift(self, trajectory: str) -> dict[str, float]:
        """Per column, how many points of % change ``trajectory`` loses (> 0) or gains at the
        check step."""
        before = {r.trajectory: r for r in self.at_step}[trajectory].change
        after = {r.trajectory: r for r in self.at_check}[trajectory].change
        return {c: after[c] - before[c] for c, _, _ in CHECKED}

    def as_dict(self, trajectory: str) -> dict:
        """For metrics.json: each trajectory's values and changes as [step, check step], and
        ``trajectory``'s shift."""
        fine = {r.trajectory: r for r in self.at_check}
        table = {
            r.trajectory: {
                **{
                    c: [round(r.values[c], 4), round(fine[r.trajectory].values[c], 4)]
                    for c, _, _ in CHECKED
                },
                **{
                    f"{c}_change": [round(r.change[c], 2), round(fine[r.trajectory].change[c], 2)]
                    for c, _, _ in CHECKED
                },
            }
            for r in self.at_step
        }
        return {
            "step": self.step,
            "check_step": self.check_step,
            "table": table,
            "shift": {c: round(v, 2) for c, v in self.shift(trajectory).items()},
        }


def step_check(
    at_step: Mapping[str, dict],
    at_check: Mapping[str, dict],
    reference: str,
    step: float,
    check_step: float,
) -> StepCheck:
    """``at_step`` and ``at_check``: CHECKED figures by trajectory, the same trajectories."""
    if set(at_step) != set(at_check):
        missing = sorted(set(at_step) ^ set(at_check))
        raise ValueError(f"the step check lacks runs of {missing} at one of the two steps")
    ordered = {name: at_check[name] for name in at_step}
    return StepCheck(
        step,
        check_step,
        table_one(at_step, reference, CHECKED),
        table_one(ordered, reference, CHECKED),
    )
