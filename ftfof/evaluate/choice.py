"""How the optimum was chosen: the candidates RHS chose among, as the simulator check measured
them, and the visit of RHS that removed each one.

RHS's last choice is among trajectories the platform simulated, each as the mean of its nominal
run and its perturbed copies. This is the trade-off the answer comes from: pull, jitter and
landing error side by side, measured. A reader sees which objective's cut decided it, and how far
the best of each objective was from the trajectory that was chosen.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ftfof.errors import DataError

# Table I's columns that measure an objective on one nominal run: the reference trajectories'
# places in the choice's figure (fs1 reads the resultant pull, fsj the detachment-window jitter)
TABLE_ANALOGUE = {"fs1": "peak_pull", "fsj": "jitter"}
CHOSEN = ""  # ``removed_by`` of the chosen candidate
TIE_BREAK = "tie-break"  # removed by Algorithm 1's lexicographic rule after alpha ran out


@dataclass(frozen=True)
class Candidate:
    """One trajectory RHS chose among: its simulated objectives (mean over ``runs``, standard
    deviation ``spread``; empty when simulated once) and what removed it."""

    row: int
    mean: dict[str, float]
    spread: dict[str, float]
    runs: int
    removed_by: str  # the objective whose visit cut it, TIE_BREAK, or CHOSEN
    visit: int  # 1-based visit of RHS that removed it (0 for the chosen one)

    @property
    def chosen(self) -> bool:
        return self.removed_by == CHOSEN


def rhs_candidates(optimum: Mapping[str, Any], objectives: Sequence[str]) -> list[Candidate]:
    """The simulator-checked candidates of an ``optimum.json`` (its ``rhs.rows``), in row order.
    Empty when RHS chose on the surrogates' predictions (no simulator check)."""
    rhs = optimum["rhs"]
    rows = [int(r) for r in rhs["rows"]]
    checked = {int(v["row"]): v for v in optimum["simulator_check"] if v["ok"]}
    if not checked:
        return []
    missing = sorted(set(rows) - set(checked))
    if missing:
        raise DataError("optimum.json", f"RHS chose among rows {missing} the check did not pass")
    removed: dict[int, tuple[str, int]] = {}
    alive = set(rows)
    for visit, step in enumerate(rhs["steps"], start=1):
        kept = {int(r) for r in step["remaining"]}
        removed.update({r: (step["objective"], visit) for r in alive - kept})
        alive = kept
    chosen = int(optimum["front_row"])
    if chosen not in alive:
        raise DataError("optimum.json", f"its front_row {chosen} is not what RHS's steps kept")
    removed.update({r: (TIE_BREAK, len(rhs["steps"]) + 1) for r in alive - {chosen}})
    removed[chosen] = (CHOSEN, 0)

    def named(values: Sequence[float]) -> dict[str, float]:
        return dict(zip(objectives, map(float, values), strict=True)) if values else {}

    return [
        Candidate(
            r,
            named(checked[r]["simulated"]),
            named(checked[r]["spread"]),
            int(checked[r]["runs"]),
            *removed[r],
        )
        for r in sorted(rows)
    ]


def fallback_order(candidates: Sequence[Candidate]) -> list[int]:
    """The rows of the candidates after the chosen one, by RHS's order: the later a visit
    removed a candidate, the closer it came to the choice (a tie-break's before any visit's);
    within one visit, the lower mean of the objective that cut it (the first where none did)."""

    def closeness(c: Candidate) -> tuple[int, float, int]:
        objective = c.removed_by if c.removed_by in c.mean else next(iter(c.mean), "")
        return -c.visit, c.mean.get(objective, np.inf), c.row

    return [c.row for c in sorted((c for c in candidates if not c.chosen), key=closeness)]


def first_that_climbs(
    rows: Sequence[int], fall_of: Callable[[int], str | None]
) -> tuple[int | None, list[dict[str, Any]]]:
    """The first of ``rows`` whose climb does not fall (``fall_of``: how a row's climb fell,
    None where it climbed), each climbed only once the one before it fell; None where every
    one fell. With the rows that fell before it and how."""
    tried: list[dict[str, Any]] = []
    for row in rows:
        fall = fall_of(row)
        if fall is None:
            return row, tried
        tried.append({"row": row, "fall": fall})
    return None, tried


def choice_summary(candidates: Sequence[Candidate]) -> dict[str, Any]:
    """The metrics of the choice: how many candidates, the lowest simulated mean of each objective
    among them against the chosen one's, and how many each objective's visits removed."""
    if not candidates:
        return {"candidates": 0}
    names = list(candidates[0].mean)
    means = np.array([[c.mean[n] for n in names] for c in candidates])
    chosen = next(c for c in candidates if c.chosen)
    removed_by = Counter(c.removed_by for c in candidates if not c.chosen)
    return {
        "candidates": len(candidates),
        "runs": min(c.runs for c in candidates),
        "lowest": {n: round(float(v), 4) for n, v in zip(names, means.min(axis=0), strict=True)},
        "chosen": {n: round(chosen.mean[n], 4) for n in names},
        "removed_by": dict(removed_by),
    }
