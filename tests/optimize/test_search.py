"""NSGA-II on the trajectory problem: seeded, feasible, recorded."""

import dataclasses

import numpy as np
import pytest

from ftfof.optimize.problem import TrajectoryProblem
from ftfof.optimize.search import Convergence, SearchSettings, search, warm_population
from ftfof.trajectory.sampling import sample_feasible

SETTINGS = SearchSettings(population=24, generations=12, seed=7, log_every=5)


@pytest.fixture(scope="module")
def problem(m3f, surrogate):
    robot = m3f.robot
    return TrajectoryProblem(
        m3f.policy,
        surrogate,
        robot.objectives,
        # no landing tolerance nor proof pull: this surrogate is untrained
        dataclasses.replace(
            m3f.rules, landing_tolerance=None, retouch_allowed=None, proof_pull=None
        ),
    )


@pytest.fixture(scope="module")
def initial(m3f):
    return m3f.policy.contract(sample_feasible(m3f.policy, SETTINGS.population, seed=3).X)


def test_search_is_deterministic_for_a_seed_and_returns_a_feasible_front(problem, initial):
    records = []
    first = search(problem, SETTINGS, initial, on_record=records.append)
    second = search(problem, SETTINGS, initial)
    np.testing.assert_array_equal(first.X, second.X)
    np.testing.assert_array_equal(first.F, second.F)
    assert first.feasible and np.all(first.G <= 0)
    assert first.generations == SETTINGS.generations
    assert first.evaluations == second.evaluations >= SETTINGS.population * SETTINGS.generations
    assert [r.generation for r in records] == [1, 5, 10, 12]
    assert list(first.history) == records
    hv = [r.hypervolume for r in records]
    # crowding truncation can shave a little hypervolume off one generation, not the trend
    assert 0 < hv[0] < hv[-1]
    # every front member is feasible for the policy itself
    assert problem.policy.check(problem.policy.expand(first.X)).feasible.all()


def test_another_seed_gives_another_front(problem, initial):
    other = SearchSettings(population=24, generations=12, seed=8, log_every=5)
    assert not np.array_equal(
        search(problem, SETTINGS, initial).F, search(problem, other, initial).F
    )


def test_hypervolume_is_normalised_by_the_first_generation():
    convergence = Convergence(every=1, last=1)
    convergence.low, convergence.span = np.zeros(2), np.ones(2)
    assert convergence.hypervolume(np.empty((0, 2))) == 0.0
    assert convergence.hypervolume(np.array([[0.0, 0.0]])) == pytest.approx(1.0)
    assert convergence.hypervolume(np.array([[0.55, 0.55]])) == pytest.approx(0.25)


def test_warm_population_puts_the_front_first_then_fills():
    front = np.array([[1.0, 1.0], [2.0, 2.0], [1.0, 1.0], [3.0, 3.0]])
    fill = np.array([[9.0, 9.0], [8.0, 8.0], [7.0, 7.0]])
    pop = warm_population(front, fill, 5)
    np.testing.assert_array_equal(pop, [[1, 1], [2, 2], [3, 3], [9, 9], [8, 8]])  # distinct
    spread = warm_population(np.arange(10.0)[:, None], fill, 4)
    np.testing.assert_array_equal(spread[:, 0], [0, 3, 6, 9])  # ends kept, evenly between
    with pytest.raises(ValueError, match="fewer than"):
        warm_population(front, fill[:1], 5)


def test_a_search_warm_started_from_a_front_keeps_its_best_first_objective(problem, initial):
    first = search(problem, SETTINGS, initial)
    fill = initial[: SETTINGS.population]
    warm = warm_population(first.X, fill, SETTINGS.population)
    short = SearchSettings(population=24, generations=3, seed=9, log_every=5)
    again = search(problem, short, warm)
    # NSGA-II keeps the extremes of its first front: nothing the last search found is lost
    assert again.feasible and again.F[:, 0].min() <= first.F[:, 0].min()
