"""Output formats of the optimiser's choice, on synthetic records."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.errors import OptimizationError
from ftfof.optimize.select import (
    Nominees,
    Verdict,
    convergence_csv,
    missing_fields,
    resolution,
    rhs_ranking,
    verified_rhs,
)


def test_convergence_csv_has_one_line_per_record():
    records = [
        {"generation": 1, "evaluations": 24, "feasible": 3, "front": 2, "hypervolume": 0.123456789},
        {"generation": 5, "evaluations": 120, "feasible": 24, "front": 9, "hypervolume": 0.5},
    ]
    assert convergence_csv(records) == (
        "generation,evaluations,feasible,front,hypervolume\n1,24,3,2,0.12345679\n5,120,24,9,0.5\n"
    )


def _cfg(**update):
    from ftfof.config import Optimize

    return Optimize().model_copy(update=update)


def _front():
    F = np.array([[0.1, 5.0], [0.9, 0.1], [0.5, 1.0], [1.0, 1.0], [0.3, 2.0]])
    return F, np.arange(10.0).reshape(5, 2)


def test_rhs_chooses_among_the_passing_candidates_on_their_simulated_objectives():
    F, X = _front()
    first, *_ = verified_rhs(F, X, np.arange(5), _cfg(), None, 5)
    second, *_ = verified_rhs(F, X, np.delete(np.arange(5), first), _cfg(), None, 5)
    simulated = {r: [0.5, 0.5] for r in range(5)}
    best = min(set(range(5)) - {first, second})  # neither of the surrogate's first two choices
    simulated[best] = [0.05, 9.0]  # the simulator's best first objective
    seen = []

    def check(rows, X_rows):
        seen.extend((row, tuple(x)) for row, x in zip(rows, X_rows, strict=True))
        return [
            Verdict(row, False, "film bent", {})
            if row == first
            else Verdict(row, True, "", {}, simulated[row])
            for row in rows
        ]

    index, rhs, rows, verdicts = verified_rhs(F, X, np.arange(5), _cfg(), check, 5)
    # every candidate simulated, in RHS's order on the predictions; the refused one dropped
    assert [v.row for v in verdicts][:2] == [first, second] and len(verdicts) == 5
    assert seen[0] == (first, tuple(X[first]))  # the check is given the row's own decision
    assert first not in rows and sorted(rows) == sorted(set(range(5)) - {first})
    # RHS on the simulated objectives: the simulator's best, not the surrogate's
    assert index == best and int(rows[rhs.index]) == index


def test_the_limit_bounds_the_simulations():
    F, X = _front()
    calls = []

    def check(rows, X_rows):
        calls.extend(rows)
        return [Verdict(row, True, "", {}, list(F[row])) for row in rows]

    index, _, rows, _ = verified_rhs(F, X, np.arange(5), _cfg(), check, 2)
    assert len(calls) == 2 and index in calls and sorted(rows) == sorted(calls)


def test_no_check_or_a_zero_limit_trusts_the_surrogates():
    F, X = _front()
    first, *_ = verified_rhs(F, X, np.arange(5), _cfg(), None, 5)

    def refuse(rows, X_rows):
        raise AssertionError("must not simulate")

    index, _, _, verdicts = verified_rhs(F, X, np.arange(5), _cfg(), refuse, 0)
    assert index == first and verdicts == []


def test_running_out_of_candidates_names_the_refusals():
    F, X = _front()
    first, *_ = verified_rhs(F, X, np.arange(5), _cfg(), None, 5)

    def refuse(rows, X_rows):
        return [Verdict(row, False, f"film bent at row {row}", {}) for row in rows]

    with pytest.raises(OptimizationError, match=rf"refused all 2 RHS .*row {first}: film"):
        verified_rhs(F, X, np.arange(5), _cfg(verify_batches=1), refuse, 2)
    with pytest.raises(OptimizationError, match="refused all 5 RHS candidates"):
        verified_rhs(F, X, np.arange(5), _cfg(), refuse, 2)  # 3 batches: the whole front
    with pytest.raises(OptimizationError, match="refused all 5"):
        verified_rhs(F, X, np.arange(5), _cfg(), refuse, 10)


def test_a_refused_batch_sends_the_next_candidates_in_rhs_order():
    F, X = _front()
    rows = np.arange(4)  # the front; row 4 is a nominee from outside it
    order = rhs_ranking(F, rows, _cfg(), 4)
    batches = []

    def check(rows, X_rows):
        batches.append(list(rows))
        return [
            Verdict(r, r == order[3], "" if r == order[3] else "shook", {}, [0.1, 0.1])
            for r in rows
        ]

    index, _, passed, verdicts = verified_rhs(F, X, rows, _cfg(), check, 2, np.array([4]))
    # the nominee joins the first batch only; the second batch is RHS's next two; no third batch
    assert batches == [[*order[:2], 4], order[2:4]]
    assert index == order[3] and passed.tolist() == [order[3]]
    assert [v.row for v in verdicts] == [*order[:2], 4, *order[2:4]]


def test_candidates_simulated_several_times_tie_within_their_repeatability():
    F, X = _front()
    # the simulator's means of the two that pass: 0.02 apart in the first objective, less than
    # a 0.1 spread over three runs can tell apart; row 1 is far better on the second
    means = {0: [1.00, 9.0], 1: [1.02, 1.0]}

    def check(rows, X_rows, spread):
        return [
            Verdict(r, True, "", {}, means[r], spread, 3)
            if r in means
            else Verdict(r, False, "x", {})
            for r in rows
        ]

    repeated = verified_rhs(F, X, np.arange(5), _cfg(), lambda r, x: check(r, x, [0.1, 0.1]), 5)
    once = verified_rhs(F, X, np.arange(5), _cfg(), lambda r, x: check(r, x, []), 5)
    assert repeated[0] == 1 and once[0] == 0


def test_the_resolution_is_the_standard_error_of_a_difference_of_means():
    passed = [Verdict(r, True, "", {}, [1.0, 2.0], [s, 2 * s], 3) for r, s in enumerate([1, 2, 3])]
    pooled = np.sqrt((1 + 4 + 9) / 3)  # root mean square: a median (2) would understate it
    np.testing.assert_allclose(resolution(passed), np.array([1, 2]) * pooled * np.sqrt(2 / 3))
    assert resolution([Verdict(0, True, "", {}, [1.0], [], 1)]) is None


def test_the_ranking_is_rhs_choice_then_its_choice_among_the_rest():
    F, _ = _front()
    ranked = rhs_ranking(F, np.arange(5), _cfg(), 3)
    rows = np.arange(5)
    for expected in ranked:  # each is RHS's choice once the earlier ones are gone
        first, *_ = verified_rhs(F, F, rows, _cfg(), None, 5)
        assert first == expected
        rows = rows[rows != first]
    assert len(set(ranked)) == 3
    assert rhs_ranking(F, np.arange(5), _cfg(), 9) == rhs_ranking(F, np.arange(5), _cfg(), 5)
    assert rhs_ranking(F, np.arange(0), _cfg(), 3) == []


def test_nominated_rows_are_simulated_beside_the_candidates_and_can_win():
    F, X = _front()
    F = np.vstack([F, [[5.0, 5.0]]])  # row 5: a nominee the surrogate thinks the worst
    X = np.vstack([X, [[10.0, 11.0]]])
    simulated = {r: [0.5, 0.5] for r in range(6)}
    simulated[5] = [0.2, 0.2]  # the simulator's best
    seen = []

    def check(rows, X_rows):
        seen.extend(rows)
        return [Verdict(r, True, "", {}, simulated[r]) for r in rows]

    index, _, rows, _ = verified_rhs(F, X, np.arange(5), _cfg(), check, 2, np.array([5]))
    assert seen == [*rhs_ranking(F, np.arange(5), _cfg(), 2), 5]  # the limit bounds the front's
    assert index == 5 and 5 in rows
    # without a check nothing measures the nominee: RHS on the front's predictions alone
    trusted = verified_rhs(F, X, np.arange(5), _cfg(), None, 2, np.array([5]))
    alone = verified_rhs(F, X, np.arange(5), _cfg(), None, 2)
    assert trusted[0] == alone[0] and list(trusted[2]) == list(alone[2]) == list(range(5))


def test_nominees_need_an_origin_per_row():
    with pytest.raises(ValueError, match="2 nominee rows but 1 origins"):
        Nominees(np.zeros((2, 12)), ["refine:1"])


def test_the_fields_a_record_lacks_are_named_by_their_dotted_path():
    record = {"robot": "mst_m3f", "rhs": {"rows": [1, 2], "steps": None}, "origin": "front"}
    fields = ("robot", "rhs.rows", "rhs.steps", "rhs.alpha", "decision", "origin.kind")
    assert missing_fields(record, fields) == ["rhs.alpha", "decision", "origin.kind"]
    assert missing_fields(record, ()) == []
