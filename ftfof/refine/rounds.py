"""A refinement round's decisions, free of files and tracking.

A round re-simulates the current optimum and front members spread along its front, measures the
surrogates' fidelity on them *before* training on them, and then either stops (the fidelity
target is met and enough of the points are clean; or nothing it simulated is new to the training
data) or adds the new points to the training data and searches again. Its clean points are also
candidates: the best of them (:func:`nominees_of`) join the next search's simulator check beside
the surrogate's (docs/optimum.md). :class:`Rounds` carries what the rounds so far left, the same
way for a round run now and for one a resumed run reads back; :class:`Round` is one round as the
report shows it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import pyarrow as pa

from ftfof.config import Dataset, Optimize, Refine, RefineTarget, Sample, Train
from ftfof.data import dataset as ds
from ftfof.data import targets
from ftfof.data.refinement import grow, round_rows
from ftfof.digests import json_sha256
from ftfof.errors import SimulationError
from ftfof.evaluate.fidelity import Fidelity, relative_error, simulated_objectives, target_met
from ftfof.evaluate.members import run_faults
from ftfof.evaluate.run import Inputs, fidelity_of, from_front
from ftfof.evaluate.runs import OPTIMUM, channels, figures_of, simulated_rows
from ftfof.optimize.select import FRONT, Nominees, Outcome, SimulatorCheck, rhs_ranking
from ftfof.robot import RobotContext
from ftfof.seeds import seed_for
from ftfof.surrogate.predict import Surrogate
from ftfof.surrogate.store import TrainingData
from ftfof.trajectory.bezier import DECISION_NAMES, same_trajectory

DIGITS = 6  # of the fidelity numbers in a round's record
ACQUIRED = "acquire"  # the origin of nominees the acquisition measured


@dataclass(frozen=True)
class Measured:
    """The acquisition's or a round's clean simulated points (the pad let go, the film
    survived, the foot landed, the body stayed within its limit): decision rows (m) and their
    objectives from the simulated forces, in priority order."""

    X: np.ndarray
    F: np.ndarray
    origin: str  # refine:<round>, or ACQUIRED


@dataclass
class Rounds:
    """What the rounds so far left for the next: the training rows each added, the clean points
    each measured, and the decision rows each round's simulator check refused (never nominated
    again: fresh copies would give a refused trajectory another draw)."""

    added: list[pa.Table] = field(default_factory=list)
    measured: list[Measured] = field(default_factory=list)
    refused: list[np.ndarray] = field(default_factory=lambda: [np.empty((0, len(DECISION_NAMES)))])

    def measure(self, points: Measured) -> None:
        """A round that trains: its clean points become candidates before its search."""
        self.measured.append(points)

    def close(self, refused: np.ndarray, rows: pa.Table) -> None:
        """A round that trained and searched: what its check refused and the rows it added."""
        self.refused.append(refused)
        self.added.append(rows)

    def nominees(self, limit: int, cfg: Optimize) -> Nominees | None:
        return nominees_of(self.measured, limit, cfg, np.vstack(self.refused))

    def unseen(self, rows: pa.Table, base: pa.Table) -> pa.Table:
        """``rows`` that neither ``base`` nor an earlier round holds."""
        return unseen(rows, [base, *self.added])


@dataclass
class Round:
    """One round as the report shows it."""

    record: dict[str, Any]  # the report's entry but the seconds (kept out of data/refine)
    target_met: bool  # the fidelity target held: nothing was added, the models were kept
    simulated: int  # simulations run by this invocation
    # none of its successful simulations was new to the training data (a front of known points,
    # or every new one failed): nothing to fine-tune on, so the rounds end with the models kept
    nothing_new: bool = False
    seconds: float = 0.0

    @property
    def last(self) -> bool:
        return self.target_met or self.nothing_new

    def line(self, first: str) -> str:
        """The round in one line: its fidelity on the ``first`` objective, the optimum
        predicted and simulated, the clean share, and how it ended."""
        r = self.record
        f = r["fidelity"][first]
        opt = r["optimum"]
        return (
            f"round {r['round']}: {self.simulated} simulated now; {first} rho {f['spearman']:.3f}, "
            f"median relative error {100 * f['median_relative_error']:.1f} %, optimum "
            f"{opt['predicted'][first]:.4g} predicted vs {opt['simulated'][first]:.4g} simulated; "
            f"{100 * r['clean_fraction']:.0f} % clean; "
            + (
                "target met, stop"
                if self.target_met
                else "nothing new to learn from, stop"
                if self.nothing_new
                else f"{r['added']} added"
            )
            + f"; {self.seconds:.1f} s"
        )


@dataclass(frozen=True)
class Verdict:
    """What a round's simulations say before any training on them."""

    fidelity: list[Fidelity]  # per objective, on the round's points
    predicted: np.ndarray  # (runs, objectives); the optimum is row 0
    simulated: np.ndarray
    clean: float  # fraction of the round's runs a real foot could run (a failed run is not)
    target_met: bool  # the refinement ends with the models and optimum kept


def judge(
    inputs: Inputs,
    ok: pd.DataFrame,
    runs: int,
    clean: int,
    ctx: RobotContext,
    surrogate: Surrogate,
    target: RefineTarget,
) -> Verdict:
    """The round's fidelity on its ``ok`` runs (of ``runs``, ``clean`` of them clean) and whether
    it meets ``target``. A nominee optimum is among the training rows: its error says nothing,
    the front's does."""
    fid, predicted, simulated = fidelity_of(inputs, ok, ctx, surrogate)
    share = clean / runs
    first = fid[0].median_relative_error
    optimum_error = (
        relative_error(predicted[0, 0], simulated[0, 0]) if from_front(inputs) else first
    )
    met = round_target_met(target, fid[0], optimum_error, share)
    return Verdict(fid, predicted, simulated, share, met)


def round_target_met(
    target: RefineTarget, first: Fidelity, optimum_error: float, clean: float
) -> bool:
    """Whether a round's points end the refinement: the first priority's fidelity (and the
    relative error at the optimum) meets the target, and enough of the points are clean."""
    fidelity_met = target_met(first, optimum_error, target.spearman, target.relative_error)
    return fidelity_met and clean >= target.clean


def successful(table: pa.Table) -> pd.DataFrame:
    """A round's successful simulations; the optimum's must be among them."""
    df = table.to_pandas()
    optimum = df[df.source == OPTIMUM]
    if optimum.empty or optimum.iloc[0].status != "ok":
        error = optimum.iloc[0].error if not optimum.empty else "missing"
        raise SimulationError(OPTIMUM, f"re-simulation failed: {error}")
    return df[df.status == "ok"]


def measured_points(ctx: RobotContext, ok: pd.DataFrame, dataset: Dataset, k: int) -> Measured:
    """Round ``k``'s successful simulations a real foot could run, with their simulated
    objectives (binned as the surrogate's targets, as the simulator check computes them)."""
    return clean_points(ctx, simulated_rows(ok), dataset, f"refine:{k}")


def acquired_points(ctx: RobotContext, table: pa.Table, dataset: Dataset) -> Measured:
    """The acquisition's sampled trajectories a real foot could run, as candidates beside the
    rounds': the simulator measured them before any surrogate existed, and on the default
    robot the best of the thousand sit ahead of where the surrogates' searches end on some
    seeds (docs/decisions/0022-acquired-nominees.md). Baselines (no decision row) are left out."""
    df = table.to_pandas()
    sampled = df[(df.status == "ok") & df[list(DECISION_NAMES)].notna().all(axis=1)]
    return clean_points(ctx, sampled, dataset, ACQUIRED)


def clean_points(ctx: RobotContext, sims: pd.DataFrame, dataset: Dataset, origin: str) -> Measured:
    """The simulations ``sims`` (acquisition rows) a real foot could run, with their simulated
    objectives (binned as the surrogate's targets, as the simulator check computes them)."""
    T3 = ctx.policy.timing.T3
    clean = [run_faults(r, figures_of(r, T3), ctx.rules).clean for _, r in sims.iterrows()]
    sims = sims[np.array(clean, dtype=bool)]
    X = sims[list(DECISION_NAMES)].to_numpy(dtype=float)
    names = ctx.robot.objectives
    F = np.empty((0, len(names)))
    if len(sims):
        force_t = targets.time_base(T3, dataset.hold, dataset.seq_len)
        runs = [channels(r) for _, r in sims.iterrows()]
        F = simulated_objectives(
            names, ctx.policy, X, runs, force_t, dataset.hold, ctx.robot.pre_pressure
        )
    return Measured(X, F, origin)


def nominees_of(
    measured: list[Measured], limit: int, cfg: Optimize, refused: np.ndarray | None = None
) -> Nominees | None:
    """The first ``limit`` of the clean points the acquisition and the rounds measured: the
    pool's non-dominated layers on the robot's first two priorities (MST-M3F: pull and body
    jitter), in RHS order (``cfg``'s alpha and beta, on every simulated objective) within a
    layer. RHS's alpha cut presumes a front: over the whole pool, whose pull runs up to 12 N,
    its first cut kept pulls to 8 N. A front of all objectives would not help: nearly every
    point is best at one of six. A trajectory simulated more than once counts once, with its
    first values; one the simulator check ``refused`` (decision rows) is left out, as is one
    with a non-finite objective. None when there are none."""
    from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

    if limit == 0 or not measured:
        return None
    X = np.vstack([m.X for m in measured])
    F = np.vstack([m.F for m in measured])
    origin = [m.origin for m in measured for _ in m.X]
    _, first = np.unique(X, axis=0, return_index=True)
    first = np.sort(first)
    keep = np.isfinite(F[first]).all(axis=1) & ~same_trajectory(X[first], refused)
    first = first[keep]
    if first.size == 0:
        return None
    ranked: list[int] = []
    for layer in NonDominatedSorting().do(F[first, :2]):
        ranked += rhs_ranking(F, first[np.sort(layer)], cfg, limit - len(ranked))
        if len(ranked) == limit:
            break
    return Nominees(X[ranked], [origin[i] for i in ranked])


def refused_rows(inputs: Inputs) -> np.ndarray:
    """The decision rows an optimum's simulator check refused."""
    rows = [v["row"] for v in inputs.optimum["simulator_check"] if not v["ok"]]
    return (
        inputs.front.loc[rows, list(DECISION_NAMES)]
        .to_numpy(float)
        .reshape(-1, len(DECISION_NAMES))
    )


def unseen(rows: pa.Table, tables: list[pa.Table]) -> pa.Table:
    """``rows`` but those whose trajectory (decision values) a table already holds: a nominee
    optimum is re-simulated in the next round, and is in the training data already (the same
    trajectory in both splits would leak into early stopping)."""
    names = list(DECISION_NAMES)
    seen = np.vstack([t.select(names).to_pandas().to_numpy(float) for t in tables])
    new = rows.select(names).to_pandas().to_numpy(float)
    return rows.filter(pa.array(~same_trajectory(new, seen)))


def nothing_new(rows: pa.Table) -> bool:
    """None of a round's unseen simulations succeeded: there is nothing to fine-tune on."""
    return "ok" not in rows.column("status").to_pylist()


def training_rows(
    simulations: pa.Table, dataset: Dataset, base_seed: int, T2: float, k: int
) -> pa.Table:
    """A round's successful simulations as dataset rows, some held out for validation (each
    round its own held-out positions)."""
    built, _ = ds.build(simulations, dataset, seed_for(base_seed, "split", k), T2)
    return round_rows(built, k)


def grown(data: TrainingData, rounds: Rounds, rows: pa.Table, key: str, k: int) -> TrainingData:
    """The training data with every round's rows and round ``k``'s ``rows``, named by the data it
    grew from, the refinement's fingerprint ``key`` and the round."""
    return TrainingData(
        grow(data.table, [*rounds.added, rows]),
        data.normalization,
        data.seq_len,
        data.hold,
        json_sha256({"dataset": data.metadata_digest, "refine": key, "round": k}, 16),
    )


def record(k: int, added: int, verdict: Verdict, names: list[str]) -> dict[str, Any]:
    """A round's entry of the refinement report, but the seconds."""

    def by_name(values) -> dict[str, float]:
        return {n: round(float(v), DIGITS) for n, v in zip(names, values, strict=True)}

    return {
        "round": k,
        "added": added,
        "clean_fraction": verdict.clean,
        "fidelity": {
            f.objective: {
                "mae": round(f.mean_abs_error, DIGITS),
                "median_relative_error": round(f.median_relative_error, DIGITS),
                "spearman": round(f.spearman, DIGITS),
            }
            for f in verdict.fidelity
        },
        "optimum": {
            "predicted": by_name(verdict.predicted[0]),
            "simulated": by_name(verdict.simulated[0]),
        },
    }


def fine_tuning(train: Train, refine: Refine) -> Train:
    """The training settings a round fine-tunes ``train.use``'s model with, from its weights."""
    update = {"losses": [train.use], "epochs": refine.epochs, "patience": refine.patience}
    return train.model_copy(update={**update, "lr": refine.lr})


def search_again(
    ctx: RobotContext,
    surrogate: Surrogate,
    models_digest: str,
    inputs: Inputs,
    cfg: Optimize,
    sample: Sample,
    search_seed: int,
    generations: int,
    surface: str,
    check: SimulatorCheck,
    nominees: Nominees | None,
) -> Outcome:
    """NSGA-II on the fine-tuned ``surrogate`` from the previous front (``inputs``'s members;
    nominees are not of the front), then RHS with the simulator's ``check`` as `optimize`
    chooses, the ``nominees`` among the candidates."""
    from ftfof.optimize.problem import TrajectoryProblem
    from ftfof.optimize.search import search
    from ftfof.optimize.select import choose
    from ftfof.optimize.setup import initial_population, search_settings

    problem = TrajectoryProblem(ctx.policy, surrogate, ctx.robot.objectives, ctx.rules)
    members = inputs.front[inputs.front.origin == FRONT]
    front = members[list(DECISION_NAMES)].to_numpy(dtype=float)
    initial = initial_population(ctx.policy, cfg, sample, search_seed, front)
    result = search(problem, search_settings(cfg, search_seed, generations), initial)
    return choose(cfg, surface, ctx, problem, result, models_digest, check, nominees)
