"""The choice among simulated candidates, read back from an optimum record: which of RHS's visits
removed each candidate, checked against the values and cuts of a real RHS trace."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from ftfof.errors import DataError
from ftfof.evaluate.choice import (
    CHOSEN,
    TIE_BREAK,
    choice_summary,
    fallback_order,
    first_that_climbs,
    rhs_candidates,
)
from ftfof.optimize.rhs import rhs_trace

NAMES = ["fs1", "fsj", "fs3"]


def _record(F: np.ndarray, rows: list[int], alpha: float = 0.4, refused: tuple[int, ...] = ()):
    """An optimum.json's choice as `optimum_record` writes it: RHS over ``F`` (one line per
    row of ``rows``), its steps as front rows, and the check's verdicts (``refused`` rows failed
    and are not among RHS's rows)."""
    trace = rhs_trace(F, [0, 1, 2], alpha, 0.9, resolution=np.zeros(3))
    spread = np.full(3, 0.01)
    verdicts = [
        {"row": r, "ok": True, "simulated": f.tolist(), "spread": spread.tolist(), "runs": 5}
        for r, f in zip(rows, F, strict=True)
    ]
    verdicts += [{"row": r, "ok": False, "simulated": [], "spread": [], "runs": 1} for r in refused]
    steps = [
        {
            **s.as_dict(),
            "objective": NAMES[s.objective],
            "remaining": [rows[i] for i in s.remaining],
        }
        for s in trace.steps
    ]
    return {
        "front_row": rows[trace.index],
        "rhs": {"rows": rows, "steps": steps, "tie_break": trace.tie_break},
        "simulator_check": verdicts,
    }


def test_each_candidate_is_removed_by_the_visit_whose_cut_it_exceeds():
    rng = np.random.default_rng(3)
    F = rng.uniform(0.0, 1.0, (30, 3))
    rows = list(range(100, 130))
    record = _record(F, rows, refused=(7, 8))
    candidates = rhs_candidates(record, NAMES)
    assert [c.row for c in candidates] == rows  # the refused rows are not candidates
    assert sum(c.chosen for c in candidates) == 1
    (chosen,) = [c for c in candidates if c.chosen]
    assert chosen.row == record["front_row"] and chosen.visit == 0
    steps = record["rhs"]["steps"]
    for c in candidates:
        assert c.mean == dict(zip(NAMES, F[c.row - 100], strict=True))
        assert c.spread == {n: 0.01 for n in NAMES} and c.runs == 5
        if c.chosen or c.removed_by == TIE_BREAK:
            continue
        step = steps[c.visit - 1]
        assert step["objective"] == c.removed_by
        assert c.mean[c.removed_by] > step["cut"]  # over the cut at its visit, under it before
        assert all(c.mean[s["objective"]] <= s["cut"] for s in steps[: c.visit - 1])
    summary = choice_summary(candidates)
    assert summary["candidates"] == 30 and summary["runs"] == 5
    assert sum(summary["removed_by"].values()) == 29
    assert summary["lowest"] == {n: round(float(F[:, j].min()), 4) for j, n in enumerate(NAMES)}
    assert summary["chosen"] == {n: round(chosen.mean[n], 4) for n in NAMES}


def test_rows_left_when_alpha_runs_out_lose_the_tie_break():
    F = np.array([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [2.0, 0.0, 0.0]])  # rows 0 and 1: a tie
    record = _record(F, [10, 11, 12], alpha=0.5)
    assert record["rhs"]["tie_break"]
    by_row = {c.row: c for c in rhs_candidates(record, NAMES)}
    assert by_row[10].removed_by == CHOSEN  # the lexicographic rule's lowest row
    assert by_row[11].removed_by == TIE_BREAK
    assert by_row[12].removed_by == "fs1" and by_row[12].visit == 1


def test_where_the_optimum_falls_the_next_is_the_one_rhs_removed_last():
    rng = np.random.default_rng(5)
    F = rng.uniform(0.0, 1.0, (30, 3))
    candidates = rhs_candidates(_record(F, list(range(30))), NAMES)
    order = fallback_order(candidates)
    chosen = next(c.row for c in candidates if c.chosen)
    assert sorted(order) == sorted(set(range(30)) - {chosen})  # every other candidate, once
    by_row = {c.row: c for c in candidates}
    visits = [by_row[r].visit for r in order]
    assert visits == sorted(visits, reverse=True)  # a later visit's before an earlier one's
    for a, b in itertools.pairwise(order):
        if by_row[a].visit == by_row[b].visit and by_row[a].removed_by != TIE_BREAK:
            cut = by_row[a].removed_by  # within a visit, the lower mean of what cut them
            assert by_row[a].mean[cut] <= by_row[b].mean[cut]


def test_a_tie_breaks_loser_comes_before_any_visits_cut():
    F = np.array([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [2.0, 0.0, 0.0]])
    candidates = rhs_candidates(_record(F, [10, 11, 12], alpha=0.5), NAMES)
    assert fallback_order(candidates) == [11, 12]
    assert fallback_order([]) == []


def test_the_choice_moves_to_the_first_that_climbs_and_climbs_no_further():
    falls = {4: "FL let go in step 3", 7: None, 9: None}
    climbed = []

    def fall_of(row: int) -> str | None:
        climbed.append(row)
        return falls[row]

    assert first_that_climbs([4, 7, 9], fall_of) == (7, [{"row": 4, "fall": falls[4]}])
    assert climbed == [4, 7]  # 9 never climbs: 7 already did
    assert first_that_climbs([4], fall_of) == (None, [{"row": 4, "fall": falls[4]}])
    assert first_that_climbs([], fall_of) == (None, [])


def test_a_choice_on_predictions_alone_has_no_candidates():
    record = {"front_row": 3, "rhs": {"rows": [1, 3], "steps": []}, "simulator_check": []}
    assert rhs_candidates(record, NAMES) == []
    assert choice_summary([]) == {"candidates": 0}


def test_a_record_whose_steps_do_not_lead_to_its_row_is_refused():
    F = np.array([[1.0, 2.0, 3.0], [2.0, 1.0, 3.0], [3.0, 3.0, 0.0]])
    record = _record(F, [0, 1, 2])
    record["front_row"] = 2  # removed by the first visit
    with pytest.raises(DataError, match="front_row 2"):
        rhs_candidates(record, NAMES)
    record = _record(F, [0, 1, 2])
    record["simulator_check"][1]["ok"] = False
    with pytest.raises(DataError, match=r"rows \[1\]"):
        rhs_candidates(record, NAMES)
