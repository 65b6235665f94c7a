"""NSGA-II on measured objectives (ftfof.optimize.polish) on MST-M3F's real rules, with an
analytic stand-in for the platform's measurements: a known optimum and a known refused region
make the search's behaviour checkable. The platform itself runs in
tests/stages/test_polish_stage.py.
"""

from dataclasses import replace

import numpy as np
import pytest

from ftfof.optimize.polish import polish, start_population
from ftfof.optimize.search import SearchSettings
from ftfof.optimize.select import Verdict
from ftfof.trajectory.sampling import sample_feasible

SETTINGS = SearchSettings(population=12, generations=8, seed=11, log_every=1)


class AnalyticPlatform:
    """Measures fs1 as the distance to ``target`` (mm) and fsj as the distance to another point;
    refuses rows whose first free value is above ``ceiling``; records what it was asked."""

    def __init__(self, policy, target, ceiling):
        self.policy, self.target, self.ceiling = policy, target, ceiling
        self.asked: list[np.ndarray] = []
        self.rows: list[int] = []

    def __call__(self, rows, X):
        self.rows += list(rows)
        self.asked.append(np.array(X))
        free = self.policy.contract(np.atleast_2d(X))
        verdicts = []
        for row, u in zip(rows, free, strict=True):
            if u[0] > self.ceiling:
                verdicts.append(Verdict(row, False, "above the ceiling", {}))
                continue
            fs1 = 1e3 * float(np.linalg.norm(u - self.target))
            fsj = 1e3 * float(np.linalg.norm(u - self.target[::-1]))
            verdicts.append(Verdict(row, True, "", {}, [fs1, fsj, 0.0], [0.01, 0.01, 0.0], 3))
        return verdicts


@pytest.fixture(scope="module")
def start(m3f):
    return sample_feasible(m3f.policy, 8, seed=4).X


@pytest.fixture(scope="module")
def platform(m3f, start):
    free = m3f.policy.contract(start)
    target = free.mean(axis=0)
    return AnalyticPlatform(m3f.policy, target, ceiling=float(np.quantile(free[:, 0], 0.75)))


@pytest.fixture(scope="module")
def polished(m3f, start, platform):
    return polish(
        m3f.policy, platform, start, SETTINGS, priorities=2, spread=1e-3, first_row=500, risk=1.0
    )


def _measured(platform, X):
    return np.array([v.simulated[:2] for v in platform(list(range(len(X))), X)])


def test_the_polish_beats_its_start_on_the_measured_objectives(m3f, start, platform, polished):
    passing = [
        v.ok
        for v in AnalyticPlatform(m3f.policy, platform.target, platform.ceiling)(
            list(range(len(start))), start
        )
    ]
    before = _measured(AnalyticPlatform(m3f.policy, platform.target, np.inf), start[passing])
    after = np.array([v.simulated[:2] for v in polished.verdicts])
    assert after[:, 0].min() < before[:, 0].min()
    assert after[:, 1].min() < before[:, 1].min()
    assert [h.generation for h in polished.history] == list(range(1, SETTINGS.generations + 1))
    assert polished.history[-1].hypervolume >= polished.history[0].hypervolume


def test_every_result_passes_the_rules_and_the_check(m3f, platform, polished):
    assert len(polished.X) > 0
    assert m3f.policy.check(polished.X).feasible.all()
    assert all(v.ok for v in polished.verdicts)
    assert (m3f.policy.contract(polished.X)[:, 0] <= platform.ceiling).all()
    assert polished.refused > 0  # the ceiling cut through the start: refusals happened
    assert polished.simulated == len(set(platform.rows)) >= len(polished.X)


def test_only_rows_that_keep_every_rule_are_simulated(m3f, platform, polished):
    asked = np.vstack(platform.asked)
    assert m3f.policy.check(asked).feasible.all()
    assert min(platform.rows) == 500 and len(set(platform.rows)) == len(platform.rows)


def test_the_polish_is_deterministic(m3f, start, platform, polished):
    fresh = AnalyticPlatform(m3f.policy, platform.target, platform.ceiling)
    again = polish(
        m3f.policy, fresh, start, SETTINGS, priorities=2, spread=1e-3, first_row=500, risk=1.0
    )
    np.testing.assert_array_equal(again.X, polished.X)


def test_a_short_start_is_filled_with_copies_in_the_box(m3f, start):
    policy = m3f.policy
    rows = start_population(start[:3], 10, 1e-3, 1, policy)
    assert rows.shape == (10, policy.n_free)
    np.testing.assert_array_equal(rows[:3], policy.contract(start[:3]))  # in their order
    assert ((rows >= policy.lower) & (rows <= policy.upper)).all()
    offsets = rows[3:] - policy.contract(start[:3])[np.arange(7) % 3]
    assert 0 < np.abs(offsets).max() < 6e-3
    np.testing.assert_array_equal(
        start_population(start, 4, 1e-3, 1, policy), policy.contract(start[:4])
    )


def test_start_verdicts_are_taken_as_measured_not_simulated_again(m3f, start, platform):
    earlier = AnalyticPlatform(m3f.policy, platform.target, platform.ceiling)
    verdicts = earlier(list(range(len(start))), start)
    fresh = AnalyticPlatform(m3f.policy, platform.target, platform.ceiling)
    short = SearchSettings(population=len(start), generations=2, seed=3)
    polish(m3f.policy, fresh, start, short, 2, 1e-3, 500, verdicts, risk=1.0)
    asked = {x.tobytes() for x in np.vstack(fresh.asked)}
    starts = m3f.policy.expand(m3f.policy.contract(start))
    assert not asked & {x.tobytes() for x in starts}
    assert len(fresh.rows) > 0  # the offspring were simulated


def test_a_trajectory_asked_again_keeps_its_first_verdict(m3f, start, platform, polished):
    """pymoo removes duplicates within a generation only: a later copy of a judged trajectory is
    not another draw of the platform."""
    from ftfof.optimize.polish import SimulatedProblem

    counting = AnalyticPlatform(m3f.policy, platform.target, platform.ceiling)
    problem = SimulatedProblem(m3f.policy, counting, 2, 0)
    U = m3f.policy.contract(start[:3])
    first, second = {}, {}
    problem._evaluate(U, first)
    problem._evaluate(U, second)
    assert len(counting.rows) == 3
    np.testing.assert_array_equal(first["F"], second["F"])


def test_best_layers_keep_whole_non_dominated_layers_of_passed_trajectories():
    from ftfof.optimize.polish import best_layers

    def verdict(ok, fs1, fsj):
        return Verdict(0, ok, "" if ok else "refused", {}, [fs1, fsj, 9.0] if ok else [])

    measured = {
        b"a": verdict(True, 1.0, 3.0),  # layer 1
        b"b": verdict(True, 3.0, 1.0),  # layer 1
        b"c": verdict(True, 2.0, 3.5),  # layer 2
        b"d": verdict(True, 3.5, 2.0),  # layer 2
        b"e": verdict(True, 4.0, 4.0),  # layer 3
        b"f": verdict(False, 0.0, 0.0),  # refused: never kept
        b"g": verdict(True, float("nan"), 0.5),  # not measured: never kept
    }
    assert best_layers(measured, 2, 2) == [b"a", b"b"]
    assert best_layers(measured, 2, 3) == [b"a", b"b", b"c", b"d"]  # the second layer whole
    assert best_layers(measured, 2, 10) == [b"a", b"b", b"c", b"d", b"e"]
    assert best_layers({b"f": measured[b"f"]}, 2, 4) == []


def test_risk_ranks_a_trajectory_by_its_mean_plus_its_spread(m3f, start):
    """With ``risk`` the search weighs a steady trajectory above one whose mean is lower but
    swings between runs; without it, the mean alone decides."""
    from ftfof.optimize.polish import SimulatedProblem

    steady = Verdict(0, True, "", {}, [6.8, 1.0, 0.0], [0.02, 0.02, 0.0], 3)
    swinging = Verdict(1, True, "", {}, [6.7, 0.9, 0.0], [0.3, 0.4, 0.0], 3)
    once = Verdict(2, True, "", {}, [6.9, 1.1, 0.0], [], 1)
    refused = Verdict(3, False, "the film bent below fc", {})
    verdicts = (steady, swinging, once, refused)

    def check(rows, X):
        return [replace(v, row=r) for v, r in zip(verdicts, rows, strict=True)]

    U = m3f.policy.contract(start[:4])
    assert m3f.policy.check(start[:4]).feasible.all()
    plain, cautious = {}, {}
    SimulatedProblem(m3f.policy, check, 2, 0)._evaluate(U, plain)
    SimulatedProblem(m3f.policy, check, 2, 0, risk=1.0)._evaluate(U, cautious)
    np.testing.assert_allclose(plain["F"][:3], [[6.8, 1.0], [6.7, 0.9], [6.9, 1.1]])
    np.testing.assert_allclose(cautious["F"][:3], [[6.82, 1.02], [7.0, 1.3], [6.9, 1.1]])
    assert (plain["F"][1] < plain["F"][0]).all() and (cautious["F"][0] < cautious["F"][1]).all()
    np.testing.assert_array_equal(cautious["G"][:, 1], [0.0, 0.0, 0.0, 1.0])  # refused stays so
