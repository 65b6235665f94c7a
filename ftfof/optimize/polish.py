"""Polish in simulation: NSGA-II whose objectives the platform measures, started from the
trajectories the simulator check passed.

The surrogate search ends where the surrogates stop telling near neighbours apart: the pull and
jitter GRUs err by more than the differences RHS weighs at the front's best, and jitter is rough
on the scale of a 0.2 mm encoder error (docs/optimum.md). A few generations of NSGA-II on the
simulator itself, each trajectory judged as the check judges it (every rule on the fine grid, the
film, the release, the landing and the body limit, over the nominal run and its perturbed copies),
move the verified candidates to where the simulator, not the surrogate, says they are better.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pymoo.core.problem import Problem

from ftfof.config import Optimize
from ftfof.config import Polish as PolishSettings
from ftfof.optimize.problem import TrajectoryProblem
from ftfof.optimize.search import ConvergenceRecord, SearchSettings, search
from ftfof.optimize.select import Outcome, SimulatorCheck, Verdict, rhs_on_verdicts
from ftfof.seeds import seed_for
from ftfof.trajectory.policy import ConstraintPolicy

Array = NDArray[np.float64]
POLISH = "polish"  # the origin of polished rows in a front table


class SimulatedProblem(Problem):
    """The robot's first ``priorities`` objectives as the simulator check measures them (the
    mean over its runs, plus ``risk`` times their standard deviation there), with two
    constraints: the rules on ``policy``'s grid (the summed violation) and the check's verdict
    (1 refused, 0 passed). Rows that break a rule are not simulated. Every simulated row's
    verdict is kept by its decision bytes."""

    def __init__(
        self,
        policy: ConstraintPolicy,
        check: SimulatorCheck,
        priorities: int,
        first_row: int,
        known: dict[bytes, Verdict] | None = None,
        risk: float = 0.0,
    ):
        super().__init__(
            n_var=policy.n_free, n_obj=priorities, n_ieq_constr=2, xl=policy.lower, xu=policy.upper
        )
        self.policy, self.check, self.priorities, self.risk = policy, check, priorities, risk
        self.known = dict(known or {})  # verdicts measured before the search: not simulated again
        self.verdicts: dict[bytes, Verdict] = {}
        self.next_row = first_row  # the row the check gets for the next simulated trajectory

    def _evaluate(self, U, out, *args, **kwargs) -> None:
        X = self.policy.expand(np.atleast_2d(U))
        rules = self.policy.check(X)
        excess = np.nansum(np.clip(rules.violations, 0.0, None), axis=1)
        broken = np.where(rules.feasible, 0.0, np.maximum(excess, 1e-12))
        refused = np.ones(len(X))
        F = np.full((len(X), self.priorities), np.nan)
        feasible = np.flatnonzero(rules.feasible)
        seen = {**self.known, **self.verdicts}  # a trajectory asked again keeps its first verdict
        run = [i for i in feasible if X[i].tobytes() not in seen]
        rows = list(range(self.next_row, self.next_row + len(run)))
        self.next_row += len(run)
        for i, verdict in zip(run, self.check(rows, X[run]) if run else [], strict=True):
            seen[X[i].tobytes()] = self.verdicts[X[i].tobytes()] = verdict
        for i in feasible:
            verdict = seen[X[i].tobytes()]
            values = self.ranked(verdict)
            if verdict.ok and values.size == self.priorities and np.isfinite(values).all():
                F[i] = values
                refused[i] = 0.0
        # pymoo ranks the unmeasured rows by their violation first; these values only keep its
        # statistics (crowding, the convergence record's scale) finite
        measured = ~np.isnan(F[:, 0])
        out["F"] = np.where(np.isnan(F), F[measured].max(axis=0) if measured.any() else 0.0, F)
        out["G"] = np.column_stack([broken, refused])

    def ranked(self, verdict: Verdict) -> np.ndarray:
        """What the search weighs of a verdict: the mean over its runs, plus ``risk`` standard
        deviations where it has them (a row simulated once has none)."""
        values = np.asarray(verdict.simulated[: self.priorities], dtype=float)
        if self.risk and len(verdict.spread) >= self.priorities:
            values = values + self.risk * np.asarray(verdict.spread[: self.priorities], dtype=float)
        return values


@dataclass(frozen=True)
class Polished:
    """The simulator's non-dominated trajectories after the polish, each with its verdict."""

    X: Array  # (k, 12) full decision rows the check passed: whole non-dominated layers
    verdicts: list[Verdict]  # in the order of X (rows as the check or the start numbered them)
    history: tuple[ConvergenceRecord, ...]  # per generation, hypervolume of the front searched on
    simulated: int  # trajectories the check judged in the search (each with its copies)
    refused: int  # of those, refused
    seconds: float


def start_population(start: Array, size: int, scale: float, seed: int, policy: ConstraintPolicy):
    """``size`` free-variable rows: the distinct ``start`` rows (full decision rows) in their
    order, then copies of them in turn with every free value off by a normal error of ``scale``,
    kept in the box. Too many start rows keep the first ``size``."""
    rows = policy.contract(np.atleast_2d(start))
    first = np.unique(rows, axis=0, return_index=True)[1]
    free = rows[np.sort(first)]
    if len(free) >= size:
        return free[:size]
    rng = np.random.default_rng(seed)
    parents = free[np.arange(size - len(free)) % len(free)]
    copies = np.clip(parents + rng.normal(0.0, scale, parents.shape), policy.lower, policy.upper)
    return np.vstack([free, copies])


def best_layers(measured: dict[bytes, Verdict], priorities: int, size: int) -> list[bytes]:
    """The passed trajectories of ``measured`` (by decision bytes) in the non-dominated layers of
    their first ``priorities`` objectives, whole layers until there are ``size`` or all are in.
    More than the final front: a later check with fresh copies may refuse some of it, and the
    choice should not then fall to whatever is left of one layer."""
    from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

    passed = [
        k
        for k, v in measured.items()
        if v.ok and np.isfinite(np.asarray(v.simulated[:priorities], dtype=float)).all()
    ]
    if not passed:
        return []
    F = np.array([measured[k].simulated[:priorities] for k in passed], dtype=float)
    keep: list[bytes] = []
    for layer in NonDominatedSorting().do(F):
        if len(keep) >= size:
            break
        keep += [passed[i] for i in sorted(layer)]
    return keep


def polish(
    policy: ConstraintPolicy,
    check: SimulatorCheck,
    start: Array,
    settings: SearchSettings,
    priorities: int,
    spread: float,
    first_row: int = 0,
    start_verdicts: Sequence[Verdict] | None = None,
    on_record: Callable[[ConvergenceRecord], None] | None = None,
    *,
    risk: float,
) -> Polished:
    """NSGA-II on :class:`SimulatedProblem` (``risk`` standard deviations over each mean) from
    ``start`` (full decision rows, filled up to the population with copies off by ``spread``).
    ``start_verdicts``, one per start row, are the check's earlier verdicts on them: taken as
    measured, not simulated again. Deterministic for the seed and the check. An empty result
    when no trajectory passed; ``on_record`` hears of each generation. The result's layers are
    those of the means: the confirmation measures them again and RHS chooses on its means."""
    started = time.perf_counter()
    as_searched = policy.expand(policy.contract(np.atleast_2d(start)))  # the bytes pymoo asks
    earlier = start_verdicts if start_verdicts is not None else [None] * len(as_searched)
    known = {x.tobytes(): v for x, v in zip(as_searched, earlier, strict=True) if v is not None}
    problem = SimulatedProblem(policy, check, priorities, first_row, known, risk)
    initial = start_population(start, settings.population, spread, settings.seed, policy)
    result = search(problem, settings, initial, on_record)
    measured = {**problem.known, **problem.verdicts}
    keys = best_layers(measured, priorities, settings.population)
    X = np.array([np.frombuffer(k) for k in keys]).reshape(len(keys), -1)
    verdicts = [measured[k] for k in keys]
    simulated = len(problem.verdicts)
    refused = sum(not v.ok for v in problem.verdicts.values())
    return Polished(X, verdicts, result.history, simulated, refused, time.perf_counter() - started)


def polish_settings(cfg: PolishSettings, opt: Optimize, search_seed: int) -> SearchSettings:
    """NSGA-II's settings on the simulator: the polish's size, the search's operators."""
    return SearchSettings(
        population=cfg.population,
        generations=cfg.generations,
        seed=seed_for(search_seed, "polish"),
        crossover_eta=opt.crossover_eta,
        crossover_prob=opt.crossover_prob,
        mutation_eta=opt.mutation_eta,
        log_every=1,
    )


def polished_outcome(
    problem: TrajectoryProblem,
    recheck: ConstraintPolicy,
    front: Array,
    origin: list[str],
    earlier: list[Verdict],
    result: Polished,
    cfg: Optimize,
) -> Outcome:
    """The previous ``front`` (full decision rows, with their ``origin`` and the check's
    ``earlier`` verdicts), the polished rows after it, RHS among the polished rows on their
    simulated objectives; every row predicted by the surrogates, for the record."""
    size = len(front)
    evaluation = problem.evaluate_population(problem.policy.contract(np.vstack([front, result.X])))
    rechecked = recheck.check(evaluation.X)
    rows = np.arange(size, size + len(result.X))
    polished = [replace(v, row=int(r)) for v, r in zip(result.verdicts, rows, strict=True)]
    rhs = rhs_on_verdicts(polished, cfg)
    index = int(rows[rhs.index])
    passing = np.flatnonzero(rechecked.feasible)
    origin = [*origin, *[POLISH] * len(rows)]
    verdicts = earlier + polished
    return Outcome(evaluation, rechecked, passing, index, rhs, rows, {}, verdicts, origin)


def polish_report(
    cfg: PolishSettings,
    names: Sequence[str],
    front_size: int,
    start_row: int,
    before: Verdict,
    result: Polished,
    outcome: Outcome,
    searched: dict[bytes, Verdict],
) -> dict[str, Any]:
    """What the polish did and what it found, against its start (front row ``start_row``) as
    the check measured it (``before``); ``searched`` holds the search's own verdicts (fixed
    draws) by decision bytes."""
    names = list(names)
    chosen = next(v for v in outcome.verdicts if v.row == outcome.index)
    in_search = searched[result.X[outcome.index - front_size].tobytes()]

    def named(values: Sequence[float]) -> dict[str, float]:
        return {n: round(float(v), 4) for n, v in zip(names, values, strict=True)}

    return {
        "polished": True,
        "generations": cfg.generations,
        "population": cfg.population,
        "objectives": names[: cfg.priorities],
        "simulated": result.simulated,
        "refused": result.refused,
        "confirm_copies": cfg.confirm_copies,
        "risk_sigmas": cfg.risk_sigmas,
        "search_seconds": round(result.seconds, 2),
        "start": {"row": start_row, "simulated": named(before.simulated)},
        "optimum": {
            "row": outcome.index,
            "simulated": named(chosen.simulated),
            "spread": named(chosen.spread) if chosen.spread else None,
            "runs": chosen.runs,
            # the same trajectory as the search measured it (its fixed draws): the gap is what
            # choosing among fixed draws flattered it by
            "searched": named(in_search.simulated),
            "predicted": named(outcome.evaluation.F[outcome.index]),
        },
        "change_vs_start": {
            n: round(100.0 * (a / b - 1.0), 2) if b else None
            for n, a, b in zip(names, chosen.simulated, before.simulated, strict=True)
        },
        "front": [named(v.simulated) for v in outcome.verdicts if v.row >= front_size],
        "history": [r.as_dict() for r in result.history],
    }
