"""Stage `optimize`: NSGA-II on the surrogates, then one trajectory by RHS -> data/optimize/.

The front is re-checked against the constraint policy on a finer time grid than the optimiser
used, and the choice is made among the rows that pass: the chosen trajectory is feasible when
checked independently of the search.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import numpy as np
import typer

from ftfof.trajectory.bezier import DECISION_NAMES

if TYPE_CHECKING:
    from ftfof.optimize.problem import PopulationEvaluation, TrajectoryProblem
    from ftfof.optimize.rhs import RHSResult
    from ftfof.optimize.search import SearchSettings
    from ftfof.trajectory.policy import FeasibilityReport
    from stages.robot import RobotContext
from stages.common import (
    ParamsOption,
    atomic_dir,
    atomic_path,
    console,
    progress,
    stage,
    write_json,
)

MODELS = Path("data/models")
OUT = Path("data/optimize")
METRICS = Path("reports/optimize.json")
CONVERGENCE = Path("reports/optimize_convergence.csv")
STAR = Path("reports/optimize_star.png")
PCP = Path("reports/optimize_pcp.png")


@dataclass
class Setup:
    """Everything a search needs, built from params and the trained models (no side effects)."""

    ctx: RobotContext
    problem: TrajectoryProblem
    settings: SearchSettings
    initial: np.ndarray | None  # free-variable rows, or None for pymoo's uniform start
    models_digest: str
    registered: dict  # target -> RegisteredWeights: the model versions resolved by alias


def prepare(params, models: Path) -> Setup:
    from ftfof.optimize.problem import TrajectoryProblem
    from ftfof.optimize.search import SearchSettings
    from ftfof.pipeline.registry import fetch_pair
    from ftfof.trajectory.sampling import sample_feasible
    from stages import tracking
    from stages.robot import robot_context
    from stages.surrogates import load_surrogate, models_digest

    ctx = robot_context(params)
    mlflow = tracking.setup(tracking.experiment_name(params.robot))
    registered = fetch_pair(mlflow, params.robot, params.train.use, params.train.alias, models)
    surrogate = load_surrogate(models, params.train.use, {t: w.path for t, w in registered.items()})
    cfg = params.optimize
    problem = TrajectoryProblem(ctx.policy, surrogate, ctx.robot.objectives, ctx.robot.pre_pressure)
    seed = params.base.seed + cfg.seed_offset
    settings = SearchSettings(
        population=cfg.population,
        generations=cfg.generations,
        seed=seed,
        crossover_eta=cfg.crossover_eta,
        crossover_prob=cfg.crossover_prob,
        mutation_eta=cfg.mutation_eta,
        log_every=cfg.log_every,
    )
    initial = None
    if cfg.seeded_start:
        s = params.sample
        drawn = sample_feasible(ctx.policy, cfg.population, seed, s.design, s.batch, s.max_draws)
        initial = ctx.policy.contract(drawn.X)
    return Setup(ctx, problem, settings, initial, models_digest(models), registered)


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    models: Annotated[Path, typer.Option(help="Trained surrogate directory.")] = MODELS,
    out: Annotated[Path, typer.Option(help="Output directory (front, optimum).")] = OUT,
    metrics: Annotated[Path, typer.Option(help="Metrics JSON.")] = METRICS,
    convergence: Annotated[Path, typer.Option(help="Convergence CSV.")] = CONVERGENCE,
    star: Annotated[Path, typer.Option(help="Star-coordinate plot (Fig. 10).")] = STAR,
    pcp: Annotated[Path, typer.Option(help="Parallel-coordinate plot.")] = PCP,
) -> None:
    """Search the trajectory space with NSGA-II on the surrogates; choose one by RHS."""
    from ftfof.optimize.search import search
    from stages.params import load_params

    params = load_params(params_path)
    setup = prepare(params, models)
    cfg = params.optimize
    tracker = _Tracker(params, setup)
    with tracker, progress(f"optimize {setup.ctx.name}") as bar:
        task = bar.add_task("generations", total=cfg.generations, info="")

        def on_record(record) -> None:
            bar.update(
                task,
                completed=record.generation,
                info=f"feasible {record.feasible}, front {record.front}, "
                f"HV {record.hypervolume:.4f}",
            )
            tracker.record(record)

        result = search(setup.problem, setup.settings, setup.initial, on_record)
        outcome = _choose(params, setup, result)
        _write(outcome, setup, result, cfg, out, metrics, convergence, star, pcp)
        artifacts = (star, pcp, convergence.with_suffix(".png"), convergence)
        tracker.finish(outcome, artifacts, optimum_digest(out))
    opt = outcome.summary["optimum"]
    objectives = ", ".join(f"{k} {v:.4g}" for k, v in opt["objectives"].items())
    console.print(
        f"{result.generations} generations, {result.evaluations:,} evaluations in "
        f"{result.seconds:.1f} s; front {len(outcome.evaluation.X)} "
        f"({outcome.summary['front']['rejected_by_recheck']} rejected on the fine grid); "
        f"optimum row {outcome.index}: {objectives} -> {out}"
    )


def optimum_digest(out: Path) -> str:
    """Identifies an optimum.json: the optimize run carries it, the evaluate run looks it up."""
    import hashlib

    return hashlib.sha256((out / "optimum.json").read_bytes()).hexdigest()[:16]


@dataclass
class Outcome:
    """The search's front, its independent recheck, and the RHS choice among the rows that pass."""

    evaluation: PopulationEvaluation  # the front sorted by objectives in priority order
    recheck: FeasibilityReport  # on the fine grid, every rule
    passing: np.ndarray  # front rows feasible on the fine grid
    index: int  # the chosen front row
    rhs: RHSResult  # over the passing rows (indices mapped back to front rows on output)
    summary: dict


def _choose(params, setup: Setup, result) -> Outcome:
    from ftfof.errors import OptimizationError
    from ftfof.optimize.rhs import rhs_trace
    from ftfof.trajectory.policy import ConstraintPolicy

    ctx, cfg = setup.ctx, params.optimize
    policy = ctx.policy
    if not result.feasible:
        worst = policy.check(policy.expand(result.X)).failed(0)
        raise OptimizationError(
            "optimize",
            f"no feasible trajectory after {result.generations} generations; the least "
            f"infeasible violates {'; '.join(worst[:3])} (try optimize.seeded_start: true or "
            "more generations)",
        )
    order = np.lexsort(result.F.T[::-1])  # priority order: first objective is the primary key
    free = result.X[order]
    evaluation = setup.problem.evaluate_population(free)
    fine = ConstraintPolicy(
        ctx.robot,
        ctx.limits,
        params.feasibility.model_copy(update={"n_t": cfg.recheck_samples}),
        ctx.name,
    )
    recheck = fine.check(evaluation.X)
    passing = np.flatnonzero(recheck.feasible)
    if passing.size == 0:
        raise OptimizationError(
            "optimize",
            f"none of the {len(free)} front members passes the recheck on "
            f"{cfg.recheck_samples} samples (first: {'; '.join(recheck.failed(0)[:3])})",
        )
    n_obj = evaluation.F.shape[1]
    rhs = rhs_trace(evaluation.F[passing], list(range(n_obj)), cfg.rhs_alpha, cfg.rhs_beta)
    index = int(passing[rhs.index])
    names = list(ctx.robot.objectives)
    final = result.history[-1]
    summary = {
        "robot": ctx.name,
        "surface": params.surface,
        "objectives": names,
        "population": cfg.population,
        "generations": result.generations,
        "evaluations": result.evaluations,
        "seconds": round(result.seconds, 2),
        "ms_per_generation": round(1e3 * result.seconds / result.generations, 2),
        "hypervolume": final.hypervolume,
        "feasible_in_final_population": final.feasible,
        "front": {
            "size": len(free),
            "passing_recheck": int(passing.size),
            "rejected_by_recheck": int(len(free) - passing.size),
            "recheck_samples": cfg.recheck_samples,
        },
        "optimum": {
            "row": index,
            "objectives": dict(zip(names, map(float, evaluation.F[index]), strict=True)),
            "decision_mm": {
                n: round(1e3 * float(v), 4)
                for n, v in zip(DECISION_NAMES, evaluation.X[index], strict=True)
            },
            "rhs_tie_break": rhs.tie_break,
        },
        "models_digest": setup.models_digest,
    }
    return Outcome(evaluation, recheck, passing, index, rhs, summary)


def _front_table(outcome: Outcome, setup: Setup):
    import pyarrow as pa

    ev, names = outcome.evaluation, list(setup.ctx.robot.objectives)
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
        "recheck_feasible": passing,
        "chosen": chosen,
    }
    meta = {
        "robot": setup.ctx.name,
        "objectives": names,
        "free_variables": list(setup.ctx.policy.free_names),
        "units": "decision variables in m; objectives in N (fs1-fs3), m (fs4, fs5), "
        "dimensionless (fs7); g: columns are violations in the rule's units, > 0 violated",
        "models_digest": setup.models_digest,
    }
    table = pa.table(columns)
    return table.replace_schema_metadata({"ftfof": json.dumps(meta, sort_keys=True)})


def _optimum(outcome: Outcome, setup: Setup, cfg) -> dict:
    """The chosen trajectory for the evaluate stage and for people: no timings, so reproducible."""
    from ftfof.trajectory.bezier import control_points

    ev, i = outcome.evaluation, outcome.index
    policy, names = setup.ctx.policy, list(setup.ctx.robot.objectives)
    timing = policy.timing
    points = control_points(ev.X[i : i + 1], policy.p0, policy.p15, timing)[0]
    rows = outcome.passing

    def step(s) -> dict:
        d = s.as_dict()
        d["objective"] = names[s.objective]
        d["remaining"] = [int(rows[r]) for r in s.remaining]  # as front rows
        return d

    fine = outcome.recheck
    return {
        "robot": setup.ctx.name,
        "front_row": i,
        "decision": dict(zip(DECISION_NAMES, map(float, ev.X[i]), strict=True)),
        "control_points": points.tolist(),
        "timing": {"T1": timing.T1, "T2": timing.T2, "T3": timing.T3},
        "objectives": dict(zip(names, map(float, ev.F[i]), strict=True)),
        "predicted": {"t": ev.t.tolist(), "Fd": ev.Fd[i].tolist(), "Fp": ev.Fp[i].tolist()},
        "rhs": {
            "alpha": cfg.rhs_alpha,
            "beta": cfg.rhs_beta,
            "among_rows": len(rows),
            "steps": [step(s) for s in outcome.rhs.steps],
            "tie_break": outcome.rhs.tie_break,
        },
        "recheck": {
            "samples": cfg.recheck_samples,
            "violation": {n: float(v) for n, v in zip(fine.names, fine.violations[i], strict=True)},
        },
        "models_digest": setup.models_digest,
    }


def _write(
    outcome: Outcome,
    setup: Setup,
    result,
    cfg,
    out: Path,
    metrics: Path,
    convergence: Path,
    star: Path,
    pcp: Path,
) -> None:
    import pyarrow.parquet as pq

    from ftfof.report.front import convergence_figure, pcp_figure, star_figure

    names = list(setup.ctx.robot.objectives)
    F, chosen = outcome.evaluation.F, outcome.index
    title = f"{setup.ctx.name}: Pareto front ({len(F)} trajectories)"
    figures = {
        star: star_figure(F, names, chosen, title),
        pcp: pcp_figure(F, names, chosen, title),
    }
    records = [r.as_dict() for r in result.history]
    with atomic_dir(out) as tmp:
        pq.write_table(_front_table(outcome, setup), tmp / "front.parquet")
        text = json.dumps(_optimum(outcome, setup, cfg), indent=2, sort_keys=True)
        (tmp / "optimum.json").write_text(text + "\n")
    write_json(metrics, outcome.summary)
    with atomic_path(convergence) as path:
        header = "generation,evaluations,feasible,front,hypervolume\n"
        lines = [
            f"{r['generation']},{r['evaluations']},{r['feasible']},{r['front']},"
            f"{r['hypervolume']:.8g}\n"
            for r in records
        ]
        path.write_text(header + "".join(lines))
    figures[convergence.with_suffix(".png")] = convergence_figure(records)
    for target, fig in figures.items():
        with atomic_path(target) as path:
            fig.savefig(path, format="png", dpi=100)


class _Tracker:
    """The stage's MLflow run: open for the whole search so the hypervolume can be watched live."""

    def __init__(self, params, setup: Setup):
        self.params, self.setup = params, setup
        self.mlflow = None
        self.run_id = ""

    def __enter__(self) -> _Tracker:
        from stages import tracking

        params, setup = self.params, self.setup
        experiment = tracking.experiment_name(params.robot)
        mlflow = tracking.setup(experiment)
        digest = setup.models_digest
        surrogate_run = tracking.latest_run(
            mlflow, experiment, "train", tracking.MODELS_DIGEST_TAG, digest
        )
        tags = {
            **tracking.tags("optimize"),
            tracking.MODELS_DIGEST_TAG: digest,
            "ftfof.surrogate_run": surrogate_run or "unknown",
        }
        if surrogate_run:
            note = tracking.link_note(mlflow, experiment, "Surrogates", surrogate_run)
            tags["mlflow.note.content"] = f"{note} (models digest {digest})."
        else:
            console.print(
                f"[yellow]no train run with models digest {digest} in this MLflow store; "
                "the optimize run is not linked to one"
            )
        self._context = mlflow.start_run(run_name="optimize", tags=tags)
        run = self._context.__enter__()
        self.mlflow, self.run_id = mlflow, run.info.run_id
        settings = {
            "optimize": params.optimize.model_dump(),
            "robot": params.robot,
            "surface": params.surface,
            "objectives": ",".join(setup.ctx.robot.objectives),
            "free_variables": ",".join(setup.ctx.policy.free_names),
            "models_digest": digest,
            "model": {t: w.uri for t, w in setup.registered.items()},
        }
        mlflow.log_params(tracking.flatten(settings))
        return self

    def __exit__(self, *exc) -> bool:
        return bool(self._context.__exit__(*exc))

    def record(self, record) -> None:
        from mlflow.entities import Metric

        stamp = int(time.time() * 1000)
        step = record.generation
        metrics = [
            Metric(k, float(getattr(record, k)), stamp, step)
            for k in ("hypervolume", "feasible", "front")
        ]
        self.mlflow.MlflowClient().log_batch(self.run_id, metrics=metrics)

    def finish(self, outcome: Outcome, artifacts: tuple[Path, ...], optimum_digest: str) -> None:
        from stages import tracking

        mlflow, summary = self.mlflow, outcome.summary
        mlflow.log_metrics(
            {
                "seconds": summary["seconds"],
                "ms_per_generation": summary["ms_per_generation"],
                "front_size": summary["front"]["size"],
                "rejected_by_recheck": summary["front"]["rejected_by_recheck"],
                **{f"optimum_{k}": v for k, v in summary["optimum"]["objectives"].items()},
            }
        )
        mlflow.log_dict(summary, "optimize.json")
        mlflow.set_tag(tracking.OPTIMUM_DIGEST_TAG, optimum_digest)
        for path in artifacts:
            mlflow.log_artifact(str(path), artifact_path="figures")
