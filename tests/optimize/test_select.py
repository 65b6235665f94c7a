"""Output formats of the optimiser's choice, on synthetic records."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.errors import OptimizationError
from ftfof.optimize.select import Verdict, convergence_csv, verified_rhs


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


def test_a_refused_rhs_choice_falls_back_to_the_next_candidate():
    F, X = _front()
    first, *_ = verified_rhs(F, X, np.arange(5), _cfg(), None, 5)
    seen = []

    def check(row, x):
        seen.append((row, tuple(x)))
        return Verdict(row, row != first, "film bent" if row == first else "", {})

    index, rhs, rows, verdicts = verified_rhs(F, X, np.arange(5), _cfg(), check, 5)
    assert [v.row for v in verdicts] == [first, index] and index != first
    assert seen[0] == (first, tuple(X[first]))  # the check is given the row's own decision
    assert first not in rows and int(rows[rhs.index]) == index
    # the fallback is RHS's choice among the remaining rows
    rest = np.delete(np.arange(5), first)
    assert index == verified_rhs(F, X, rest, _cfg(), None, 5)[0]


def test_no_check_or_a_zero_limit_trusts_the_surrogates():
    F, X = _front()
    first, *_ = verified_rhs(F, X, np.arange(5), _cfg(), None, 5)

    def refuse(row, x):
        raise AssertionError("must not simulate")

    index, _, _, verdicts = verified_rhs(F, X, np.arange(5), _cfg(), refuse, 0)
    assert index == first and verdicts == []


def test_running_out_of_candidates_names_the_refusals():
    F, X = _front()
    first, *_ = verified_rhs(F, X, np.arange(5), _cfg(), None, 5)

    def refuse(row, x):
        return Verdict(row, False, f"film bent at row {row}", {})

    with pytest.raises(OptimizationError, match=rf"refused the first 2 RHS .*row {first}: film"):
        verified_rhs(F, X, np.arange(5), _cfg(), refuse, 2)
    with pytest.raises(OptimizationError, match="refused the first 5"):
        verified_rhs(F, X, np.arange(5), _cfg(), refuse, 10)
