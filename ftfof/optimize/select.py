"""From a search to one trajectory: recheck the front, choose by RHS, and the output tables.

The front is re-checked against the constraint policy on a finer time grid than the optimiser
used, and the choice is made among the rows that pass: the chosen trajectory is feasible when
checked independently of the search.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pyarrow as pa

from ftfof.config import Optimize
from ftfof.errors import OptimizationError
from ftfof.optimize.problem import PopulationEvaluation, TrajectoryProblem
from ftfof.optimize.rhs import RHSResult, rhs_trace
from ftfof.optimize.search import SearchResult
from ftfof.robot import RobotContext
from ftfof.trajectory.bezier import DECISION_NAMES, control_points
from ftfof.trajectory.policy import ConstraintPolicy, FeasibilityReport


@dataclass
class Outcome:
    """The search's front (and any nominees after it), its independent recheck, and the RHS
    choice among the rows that pass. A "row" indexes ``evaluation``: the front's, then the
    nominees'."""

    evaluation: PopulationEvaluation  # the front sorted in priority order, then the nominees
    recheck: FeasibilityReport  # on the fine grid, every rule
    passing: np.ndarray  # rows feasible on the fine grid
    index: int  # the chosen row
    rhs: RHSResult  # over ``rhs_rows`` (indices mapped back to rows on output)
    rhs_rows: np.ndarray  # the passing rows the simulator has not refused
    summary: dict[str, Any]  # the stage's metrics
    verdicts: list[Verdict]  # simulator checks, in RHS order
    origin: list[str]  # per row: "front", or the nominee's origin


FRONT = "front"  # the origin of the search's own front rows


@dataclass(frozen=True)
class Nominees:
    """Trajectories the simulator has already run clean, put up for the simulator check beside
    the surrogate's candidates (refinement's measured points): full decision rows (m) and where
    each was simulated (e.g. ``refine:2``)."""

    X: np.ndarray
    origin: list[str]

    def __post_init__(self) -> None:
        if len(self.X) != len(self.origin):
            raise ValueError(f"{len(self.X)} nominee rows but {len(self.origin)} origins")


@dataclass(frozen=True)
class Verdict:
    """One RHS candidate re-simulated: does a real foot survive it, and what was measured."""

    row: int
    ok: bool
    reason: str  # why it was refused ("" when ok)
    measured: dict[str, float]
    # the robot's objectives from the simulated forces, in priority order (empty when it failed):
    # the mean over ``runs`` simulations (the row and its copies with perturbed control values)
    simulated: list[float] = field(default_factory=list)
    spread: list[float] = field(default_factory=list)  # their standard deviation over the runs
    runs: int = 1


# Simulates decision rows ``X`` (one per front row in ``rows``, for the record) and judges each.
SimulatorCheck = Callable[[Sequence[int], np.ndarray], list[Verdict]]


def choose(
    cfg: Optimize,
    surface: str,
    ctx: RobotContext,
    problem: TrajectoryProblem,
    result: SearchResult,
    models_digest: str,
    check: SimulatorCheck | None = None,
    nominees: Nominees | None = None,
) -> Outcome:
    """Recheck the front on ``optimize.recheck_samples`` points; RHS among the rows that pass.

    With ``check``, the surrogate proposes and the simulator disposes (:func:`verified_rhs`):
    the first ``optimize.verify_candidates`` RHS candidates are re-simulated, those the simulator
    refuses (in any of its runs: the film bent below its limit, a pad that does not let go
    cleanly, a landing outside the robot's tolerance, a body shaken past its limit, a failed
    run) are dropped, and RHS chooses among the rest on their simulated objectives (the mean over
    the runs). ``nominees`` join the candidates as rows after the front's (predicted by the
    surrogates like them, for the record); without a check (or with ``verify_candidates`` 0)
    they are left out: nothing would measure them against the front.
    """
    policy = ctx.policy
    if not result.feasible:
        raise _none_feasible(problem, policy, result)
    order = np.lexsort(result.F.T[::-1])  # priority order: first objective is the primary key
    free = result.X[order]
    size = len(free)
    origin = [FRONT] * size
    limit = cfg.verify_candidates if check is not None else 0
    if nominees is not None and limit > 0 and len(nominees.X):
        free = np.vstack([free, policy.contract(nominees.X)])
        origin += nominees.origin
    evaluation = problem.evaluate_population(free)
    recheck = fine_policy(ctx, cfg.recheck_samples).check(evaluation.X)
    passing = np.flatnonzero(recheck.feasible)
    members, nominated = passing[passing < size], passing[passing >= size]
    if members.size == 0:
        raise OptimizationError(
            "optimize",
            f"none of the {size} front members passes the recheck on "
            f"{cfg.recheck_samples} samples (first: {'; '.join(recheck.failed(0)[:3])})",
        )
    index, rhs, candidates, verdicts = verified_rhs(
        evaluation.F, evaluation.X, members, cfg, check, limit, nominated
    )
    summary = {
        **_search_summary(cfg, surface, ctx, problem, result),
        "front": {
            "size": size,
            "passing_recheck": int(members.size),
            "rejected_by_recheck": int(size - members.size),
            "recheck_samples": cfg.recheck_samples,
        },
        "nominated": {"size": len(free) - size, "passing_recheck": int(nominated.size)},
        "optimum": _optimum_summary(list(ctx.robot.objectives), evaluation, index, rhs, origin),
        "simulator_check": [v.__dict__ for v in verdicts],
        "models_digest": models_digest,
    }
    return Outcome(evaluation, recheck, passing, index, rhs, candidates, summary, verdicts, origin)


def _none_feasible(
    problem: TrajectoryProblem, policy: ConstraintPolicy, result: SearchResult
) -> OptimizationError:
    """The error of a search that found no feasible trajectory, naming what the least infeasible
    one violates (the robot's rules, then the predicted physical limits)."""
    least = problem.evaluate_population(result.X[:1])
    worst = policy.check(least.X).failed(0)
    worst += [
        f"{name} (predicted g = {float(g[0]):.3g})"
        for name, g in least.physical.items()
        if g[0] > 0
    ]
    hint = "try optimize.seeded_start: true or more generations; a physical limit the surrogate "
    hint += "predicts nowhere met needs a surrogate trained on more data"
    if least.physical.get("pad_holds", [0.0])[0] > 0:  # no acquired landing may hold F_proof
        hint += f"; where reports/acquire.json's holds_fraction is 0, lower robots.{policy.name}"
        hint += ".proof.safety_factor or set its refuse: false"
    return OptimizationError(
        "optimize",
        f"no feasible trajectory after {result.generations} generations; the least "
        f"infeasible violates {'; '.join(worst[:3])} ({hint})",
    )


def _search_summary(
    cfg: Optimize, surface: str, ctx: RobotContext, problem: TrajectoryProblem, result: SearchResult
) -> dict[str, Any]:
    """The summary's account of the search: what was searched, how long, how it converged."""
    final = result.history[-1]
    return {
        "robot": ctx.name,
        "surface": surface,
        "objectives": list(ctx.robot.objectives),
        "population": cfg.population,
        "generations": result.generations,
        "evaluations": result.evaluations,
        "seconds": round(result.seconds, 2),
        "ms_per_generation": round(1e3 * result.seconds / result.generations, 2),
        "hypervolume": final.hypervolume,
        "feasible_in_final_population": final.feasible,
        "physical_limits": list(problem.physical),
    }


def _optimum_summary(
    names: list[str],
    evaluation: PopulationEvaluation,
    index: int,
    rhs: RHSResult,
    origin: list[str],
) -> dict[str, Any]:
    """The chosen row in the summary: its predicted objectives and control values (mm)."""
    return {
        "row": index,
        "objectives": dict(zip(names, map(float, evaluation.F[index]), strict=True)),
        "decision_mm": {
            n: round(1e3 * float(v), 4)
            for n, v in zip(DECISION_NAMES, evaluation.X[index], strict=True)
        },
        "rhs_tie_break": rhs.tie_break,
        "origin": origin[index],
    }


def fine_policy(ctx: RobotContext, recheck_samples: int) -> ConstraintPolicy:
    """The robot's rules on ``recheck_samples`` points: the recheck every chosen trajectory
    passes, independently of the grid the search used."""
    fine = ctx.policy.feasibility.model_copy(update={"n_t": recheck_samples})
    return ConstraintPolicy(ctx.robot, ctx.limits, fine, ctx.name)


def verified_rhs(
    F: np.ndarray,
    X: np.ndarray,
    rows: np.ndarray,
    cfg: Optimize,
    check: SimulatorCheck | None,
    limit: int,
    nominated: np.ndarray | None = None,
) -> tuple[int, RHSResult, np.ndarray, list[Verdict]]:
    """RHS on the predicted objectives ``F`` ranks ``limit`` candidates among ``rows``
    (:func:`rhs_ranking`), the ``nominated`` rows join them; they are simulated together, and RHS
    chooses again among those the check passes, on their *simulated* objectives: the surrogates
    are off by more than the differences RHS weighs near the front's best, the simulator is not.
    Where the check simulated each candidate several times, differences within the simulator's
    own repeatability are ties (:func:`resolution`).

    When the check refuses every candidate of a batch, the next ``limit`` rows in RHS order are
    simulated, up to ``cfg.verify_batches`` batches: a retrained surrogate (another seed, another
    machine's last bits) can put its first candidates just past a limit the simulator judges,
    and the front holds more than ``limit`` rows to try before giving up.

    Returns the chosen row, its RHS trace (over the returned rows), the rows it ran over and the
    verdicts in order. None passing in any batch is an OptimizationError naming the first
    refusals. ``limit`` 0 (or no check) trusts the surrogates: RHS on ``F`` over ``rows``,
    nominees ignored.
    """
    priority = list(range(F.shape[1]))
    if check is None or limit == 0:
        rhs = rhs_trace(F[rows], priority, cfg.rhs_alpha, cfg.rhs_beta)
        return int(rows[rhs.index]), rhs, rows, []
    extra = [] if nominated is None else [int(r) for r in nominated]
    ranked = rhs_ranking(F, rows, cfg, limit * cfg.verify_batches)
    verdicts: list[Verdict] = []
    for start in range(0, len(ranked), limit):
        batch = ranked[start : start + limit] + (extra if start == 0 else [])
        verdicts += check(batch, X[batch])
        if any(v.ok for v in verdicts):
            break
    passed = [v for v in verdicts if v.ok]
    if not passed:
        refused = "; ".join(f"row {v.row}: {v.reason}" for v in verdicts[:3])
        raise OptimizationError(
            "optimize",
            f"the simulator refused all {len(verdicts)} RHS candidates it was given, in "
            f"batches of {limit} ({refused}); raise "
            "optimize.verify_candidates or optimize.verify_batches, or retrain the surrogates "
            "where they fail",
        )
    rhs = rhs_on_verdicts(passed, cfg)
    return passed[rhs.index].row, rhs, np.array([v.row for v in passed]), verdicts


def rhs_on_verdicts(passed: Sequence[Verdict], cfg: Optimize) -> RHSResult:
    """RHS among candidates the simulator check passed, on their simulated objectives (in
    priority order); differences within the check's resolution are ties."""
    simulated = np.array([v.simulated for v in passed], dtype=float)
    priority = list(range(simulated.shape[1]))
    return rhs_trace(simulated, priority, cfg.rhs_alpha, cfg.rhs_beta, resolution(passed))


def rhs_ranking(F: np.ndarray, rows: np.ndarray, cfg: Optimize, limit: int) -> list[int]:
    """The first ``limit`` of ``rows`` in RHS order: RHS's choice on ``F``, then its choice among
    the rest, and so on."""
    priority = list(range(F.shape[1]))
    ranked: list[int] = []
    while rows.size and len(ranked) < limit:
        index = int(rows[rhs_trace(F[rows], priority, cfg.rhs_alpha, cfg.rhs_beta).index])
        ranked.append(index)
        rows = rows[rows != index]
    return ranked


def resolution(passed: Sequence[Verdict]) -> np.ndarray | None:
    """Per objective, the standard error of the difference of two candidates' simulated means:
    the pooled spread (root mean square over the candidates: each spread comes from a few runs,
    and their median would understate it) times sqrt(2 / runs). Closer means are ties for RHS.
    None when the candidates were simulated once each (no spread to go by)."""
    if not passed or any(not v.spread for v in passed):
        return None
    pooled = np.sqrt(np.mean(np.square([v.spread for v in passed]), axis=0))
    return pooled * np.sqrt(2.0 / min(v.runs for v in passed))


def front_table(outcome: Outcome, ctx: RobotContext, models_digest: str) -> pa.Table:
    """Every row (the front's, then any nominees'): decision, objectives, violations, recheck,
    choice and origin; units in metadata."""
    ev, names = outcome.evaluation, list(ctx.robot.objectives)
    rules = ev.violations.names
    chosen = np.zeros(len(ev.X), dtype=bool)
    chosen[outcome.index] = True
    passing = np.zeros(len(ev.X), dtype=bool)
    passing[outcome.passing] = True
    columns = {
        "row": np.arange(len(ev.X), dtype=np.int64),
        **{n: ev.X[:, j] for j, n in enumerate(DECISION_NAMES)},
        **{n: ev.F[:, j] for j, n in enumerate(names)},
        **{f"g:{rule}": ev.violations.violations[:, j] for j, rule in enumerate(rules)},
        **{f"g:{name}": g for name, g in ev.physical.items()},
        "recheck_feasible": passing,
        "chosen": chosen,
        "origin": outcome.origin,
    }
    meta = {
        "robot": ctx.name,
        "objectives": names,
        "free_variables": list(ctx.policy.free_names),
        "units": "decision variables in m; objectives in N (fs1-fs3), m (fs4, fs5), "
        "dimensionless (fs7), m/s^2 (fsj); g: columns are violations in the rule's units "
        "(film_safety: limit * max curvature - 1; pad_clearance: 1 - max clearance / required; "
        "pad_retouch: max bonds re-formed in the swing / allowed - 1; "
        "landing_press: |max landing Fp - a| / (tolerance * a) - 1; "
        "pad_holds: 1 - max proof verdict / 0.5; all predicted), > 0 violated",
        "models_digest": models_digest,
    }
    table = pa.table(columns)
    return table.replace_schema_metadata({"ftfof": json.dumps(meta, sort_keys=True)})


def optimum_record(
    outcome: Outcome, ctx: RobotContext, cfg: Optimize, models_digest: str
) -> dict[str, Any]:
    """The chosen trajectory for the evaluate stage and for people: no timings, so reproducible."""
    ev, i = outcome.evaluation, outcome.index
    policy, names = ctx.policy, list(ctx.robot.objectives)
    timing = policy.timing
    points = control_points(ev.X[i : i + 1], policy.p0, policy.p15, timing)[0]
    rows = outcome.rhs_rows

    def step(s) -> dict:
        d = s.as_dict()
        d["objective"] = names[s.objective]
        d["remaining"] = [int(rows[r]) for r in s.remaining]  # as rows of front.parquet
        return d

    fine = outcome.recheck
    return {
        "robot": ctx.name,
        "front_row": i,
        "origin": outcome.origin[i],
        "decision": dict(zip(DECISION_NAMES, map(float, ev.X[i]), strict=True)),
        "control_points": points.tolist(),
        "timing": {"T1": timing.T1, "T2": timing.T2, "T3": timing.T3},
        "objectives": dict(zip(names, map(float, ev.F[i]), strict=True)),
        "predicted": {"t": ev.t.tolist(), **{k: v[i].tolist() for k, v in ev.series.items()}},
        "rhs": {
            "alpha": cfg.rhs_alpha,
            "beta": cfg.rhs_beta,
            "resolution": dict(zip(names, outcome.rhs.resolution, strict=True))
            if outcome.rhs.resolution
            else None,
            "rows": [int(r) for r in rows],  # the rows RHS chose among
            "steps": [step(s) for s in outcome.rhs.steps],
            "tie_break": outcome.rhs.tie_break,
        },
        "recheck": {
            "samples": cfg.recheck_samples,
            "violation": {n: float(v) for n, v in zip(fine.names, fine.violations[i], strict=True)},
        },
        "simulator_check": [v.__dict__ for v in outcome.verdicts],
        "models_digest": models_digest,
    }


def missing_fields(record: dict[str, Any], fields: Sequence[str]) -> list[str]:
    """Those of ``fields`` (dotted: inside a section) that ``record`` (an optimum record, say)
    lacks."""

    def present(path: str) -> bool:
        node: Any = record
        for key in path.split("."):
            if not isinstance(node, dict) or key not in node:
                return False
            node = node[key]
        return True

    return [f for f in fields if not present(f)]


def convergence_csv(records: list[dict[str, Any]]) -> str:
    """The convergence history as CSV text: one line per logged generation."""
    header = "generation,evaluations,feasible,front,hypervolume\n"
    lines = [
        f"{r['generation']},{r['evaluations']},{r['feasible']},{r['front']},"
        f"{r['hypervolume']:.8g}\n"
        for r in records
    ]
    return header + "".join(lines)
