"""Redundancy hierarchical strategy (FTFOF Algorithm 1, §V.C)."""

import numpy as np
import pytest

from ftfof.optimize.rhs import rhs_trace

WORKED = np.array(
    [
        [5.4, 0.2, 1.0, 3.0, 10],
        [5.6, 0.1, 0.5, 2.5, 9],
        [6.1, 0.0, 0.2, 2.0, 8],
        [5.5, 0.3, 0.1, 2.8, 12],
        [7.0, 0.05, 0.0, 1.0, 7],
    ]
)


def test_worked_example_from_the_design():
    result = rhs_trace(WORKED, [0, 1, 2, 3, 4])
    assert result.index == 2 and not result.tie_break
    cuts = [s.cut for s in result.steps]
    np.testing.assert_allclose(cuts, [6.84, 0.27, 0.848, 2.32805], rtol=0, atol=1e-12)
    assert [s.remaining for s in result.steps] == [(0, 1, 2, 3), (0, 1, 2), (1, 2), (2,)]
    # alpha shrinks by beta^k after the k-th visit: 0.9, 0.9, 0.81, 0.6561
    np.testing.assert_allclose([s.alpha for s in result.steps], [0.9, 0.9, 0.81, 0.6561])


def test_priority_order_changes_the_choice():
    F = np.array([[0.0, 1.0], [1.0, 0.0]])
    assert rhs_trace(F, [0, 1]).index == 0 and rhs_trace(F, [1, 0]).index == 1


def test_single_row_front_is_its_own_choice():
    result = rhs_trace(WORKED[1:2], [0, 1])
    assert result.index == 0 and result.steps == ()


def test_the_minimum_of_the_visited_objective_always_survives():
    rng = np.random.default_rng(3)
    for _ in range(50):
        F = rng.random((12, 3))
        for step in rhs_trace(F, [2, 0, 1]).steps:
            assert F[list(step.remaining), step.objective].min() == pytest.approx(step.low)


def test_exact_ties_fall_back_to_lexicographic_then_lowest_row():
    F = np.array([[1.0, 2.0], [1.0, 1.0], [1.0, 1.0], [1.0, 3.0]])
    # column 0 is constant; column 1 keeps rows 1 and 2 (exact tie) until alpha underflows
    result = rhs_trace(F, [0, 1])
    assert result.tie_break and result.index == 1


def test_a_difference_within_the_resolution_is_a_tie_and_the_next_priority_decides():
    F = np.array([[1.00, 9.0], [1.03, 2.0]])
    assert rhs_trace(F, [0, 1], alpha=0.5).index == 0  # Algorithm 1: 0.03 decides
    result = rhs_trace(F, [0, 1], alpha=0.5, resolution=[0.05, 0.0])
    assert result.index == 1  # 1.00 and 1.03 are one value; the second objective chooses
    assert result.steps[0].cut == pytest.approx(1.05) and result.steps[0].remaining == (0, 1)
    assert rhs_trace(F, [0, 1], alpha=0.5, resolution=[0.0, 0.0]).index == 0  # 0: the paper's


def test_a_resolution_wider_than_every_range_ends_in_the_lexicographic_rule():
    F = np.array([[1.0, 2.0], [1.1, 1.0]])
    result = rhs_trace(F, [0, 1], resolution=[1.0, 5.0])
    assert result.tie_break and result.index == 0


@pytest.mark.parametrize("resolution", [[0.1], [0.1, -0.1]])
def test_a_malformed_resolution_is_named(resolution):
    with pytest.raises(ValueError, match="resolution must be 2 values >= 0"):
        rhs_trace(np.ones((3, 2)), [0, 1], resolution=resolution)


def test_constant_front_keeps_every_row_and_picks_the_first():
    result = rhs_trace(np.ones((4, 3)), [0, 1, 2])
    assert result.index == 0 and result.tie_break
    assert all(s.remaining == (0, 1, 2, 3) for s in result.steps)


@pytest.mark.parametrize(
    ("F", "priority", "alpha", "beta", "message"),
    [
        (np.empty((0, 2)), [0], 0.9, 0.9, "non-empty"),
        (np.ones(3), [0], 0.9, 0.9, "non-empty"),
        (np.array([[1.0, np.nan]]), [0], 0.9, 0.9, "NaN"),
        (np.ones((2, 2)), [2], 0.9, 0.9, "priority"),
        (np.ones((2, 2)), [], 0.9, 0.9, "priority"),
        (np.ones((2, 2)), [0], 0.0, 0.9, "alpha"),
        (np.ones((2, 2)), [0], 0.9, 1.0, "beta"),
    ],
)
def test_invalid_input_is_named(F, priority, alpha, beta, message):
    with pytest.raises(ValueError, match=message):
        rhs_trace(F, priority, alpha, beta)
