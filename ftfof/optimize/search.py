"""NSGA-II over a trajectory problem, with a convergence record (FTFOF §V.B).

The initial population can be seeded with feasible trajectories: for robots whose feasible set is
a sliver of the box (MST-M3F accepts about 5e-4 of uniform draws) a uniform start spends hundreds
of generations only finding feasibility.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import moocore
import numpy as np
from numpy.typing import NDArray
from pymoo.algorithms.moo.nsga2 import NSGA2
from pymoo.core.callback import Callback
from pymoo.core.problem import Problem
from pymoo.operators.crossover.sbx import SBX
from pymoo.operators.mutation.pm import PM

Array = NDArray[np.float64]
REFERENCE = 1.1  # hypervolume reference point, in objectives normalised by the first generation


@dataclass(frozen=True)
class SearchSettings:
    population: int
    generations: int
    seed: int
    crossover_eta: float = 15.0
    crossover_prob: float = 0.9
    mutation_eta: float = 20.0
    log_every: int = 10  # generations between hypervolume records


@dataclass(frozen=True)
class ConvergenceRecord:
    generation: int
    evaluations: int
    feasible: int  # feasible members of the current population
    front: int  # size of the current feasible non-dominated set
    # Volume the feasible front dominates, in units of the box [min, 1.1 max] of the first
    # generation's objectives: it grows as the front improves and passes 1 once the front goes
    # below the first generation's minima.
    hypervolume: float

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class SearchResult:
    X: Array  # (k, n_var) the final non-dominated set (or the least infeasible individual)
    F: Array  # (k, n_obj)
    G: Array  # (k, n_constr) as posed to pymoo (scaled)
    feasible: bool  # False when no feasible individual was found
    history: tuple[ConvergenceRecord, ...]
    generations: int
    evaluations: int
    seconds: float


class Convergence(Callback):
    """Feasible count and hypervolume of the feasible front every ``every`` generations.

    Objectives are normalised by the range of the first generation, kept fixed so that the
    hypervolume of later generations is comparable with earlier ones.
    """

    def __init__(
        self,
        every: int,
        last: int,
        on_record: Callable[[ConvergenceRecord], None] | None = None,
    ):
        super().__init__()
        self.every, self.last, self.on_record = every, last, on_record
        self.low: Array | None = None
        self.span: Array | None = None
        self.records: list[ConvergenceRecord] = []
        self.generation = 0

    def notify(self, algorithm) -> None:
        gen = self.generation = algorithm.n_gen
        pop = algorithm.pop
        if self.low is None:
            F = pop.get("F")
            span = np.ptp(F, axis=0)
            self.low, self.span = F.min(axis=0), np.where(span > 0, span, 1.0)
        if gen == 1 or gen % self.every == 0 or gen == self.last:
            feasible = int(np.sum(pop.get("CV")[:, 0] <= 0))  # a Python loop in pymoo: only here
            opt = algorithm.opt
            front = opt[opt.get("CV")[:, 0] <= 0].get("F") if len(opt) else np.empty((0, 1))
            record = ConvergenceRecord(
                gen, algorithm.evaluator.n_eval, feasible, len(front), self.hypervolume(front)
            )
            self.records.append(record)
            if self.on_record is not None:
                self.on_record(record)

    def hypervolume(self, front: Array) -> float:
        if len(front) == 0:
            return 0.0
        assert self.low is not None and self.span is not None
        scaled = (front - self.low) / self.span
        n_obj = scaled.shape[1]
        ref = np.full(n_obj, REFERENCE)
        return float(moocore.hypervolume(scaled, ref=ref)) / REFERENCE**n_obj


def search(
    problem: Problem,
    settings: SearchSettings,
    initial: Array | None = None,
    on_record: Callable[[ConvergenceRecord], None] | None = None,
) -> SearchResult:
    """Run NSGA-II for ``settings.generations`` generations, deterministic for the seed."""
    algorithm = NSGA2(
        pop_size=settings.population,
        sampling=initial if initial is not None else _uniform(),
        crossover=SBX(eta=settings.crossover_eta, prob=settings.crossover_prob),
        mutation=PM(eta=settings.mutation_eta),
        eliminate_duplicates=True,
        return_least_infeasible=True,
    )
    convergence = Convergence(settings.log_every, settings.generations, on_record)
    started = time.perf_counter()
    algorithm.setup(
        problem,
        termination=("n_gen", settings.generations),
        seed=settings.seed,
        callback=convergence,
        verbose=False,
    )
    while algorithm.has_next():
        algorithm.next()
    seconds = time.perf_counter() - started
    result = algorithm.result()
    X, F, G = (np.atleast_2d(result.opt.get(k)) for k in ("X", "F", "G"))
    feasible = bool(np.all(result.opt.get("CV")[:, 0] <= 0))
    return SearchResult(
        X,
        F,
        G,
        feasible,
        tuple(convergence.records),
        convergence.generation,
        algorithm.evaluator.n_eval,
        seconds,
    )


def warm_population(front: Array, fill: Array, size: int) -> Array:
    """A first population of ``size`` rows: a previous front (its distinct rows, in order), then
    rows of ``fill`` up to ``size``. A front larger than ``size`` keeps ``size`` rows spread evenly
    along it. Warm-starts a search on updated surrogates where the last one ended."""
    front = np.unique(np.atleast_2d(front), axis=0, return_index=True)
    rows = front[0][np.argsort(front[1])]  # distinct, in the front's order
    if len(rows) >= size:
        return rows[np.round(np.linspace(0, len(rows) - 1, size)).astype(int)]
    need = size - len(rows)
    if len(fill) < need:
        raise ValueError(f"{len(rows)} front rows and {len(fill)} fill rows are fewer than {size}")
    return np.vstack([rows, np.atleast_2d(fill)[:need]])


def _uniform():
    from pymoo.operators.sampling.rnd import FloatRandomSampling

    return FloatRandomSampling()
