"""The `optimize` run: the search set up from params and the registered surrogates, its outputs,
and its MLflow run (open for the whole search, so the hypervolume can be watched live)."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ftfof.config import Params
from ftfof.digests import models_digest
from ftfof.files import atomic_path, save_figure
from ftfof.optimize.problem import TrajectoryProblem
from ftfof.optimize.search import (
    ConvergenceRecord,
    SearchResult,
    SearchSettings,
    search,
)
from ftfof.optimize.select import (
    Outcome,
    choose,
    convergence_csv,
)
from ftfof.optimize.setup import initial_population, search_settings
from ftfof.pipeline import tracking
from ftfof.pipeline.artefacts import optimum_digest, write_optimum
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.console import console
from ftfof.pipeline.registry import RegisteredWeights, fetch_model
from ftfof.pipeline.simcheck import simulator_check_of
from ftfof.pipeline.summaries import write_metrics
from ftfof.report import run_metrics
from ftfof.robot import RobotContext

if TYPE_CHECKING:
    from ftfof.surrogate.predict import Surrogate


@dataclass
class Setup:
    """Everything a search needs, built from params and the trained models (no side effects)."""

    ctx: RobotContext
    problem: TrajectoryProblem
    settings: SearchSettings
    initial: np.ndarray | None  # free-variable rows, or None for pymoo's uniform start
    models_digest: str
    registered: RegisteredWeights | None  # the model version resolved by alias (None in refine)


@dataclass(frozen=True)
class Outputs:
    out: Path  # directory: front.parquet, optimum.json
    metrics: Path
    convergence: Path  # CSV; its PNG goes beside it
    star: Path
    pcp: Path


def prepare(params: Params, models: Path) -> Setup:
    """The stage's search: the surrogates the registry's alias names, checked against ``models``."""
    from ftfof.surrogate.store import load_surrogate

    mlflow = tracking.setup(tracking.experiment_name(params.robot))
    registered = fetch_model(mlflow, params.robot, params.train.use, params.train.alias, models)
    if registered.moved_from is not None:
        console.print(
            f"[yellow]{registered.name}@{params.train.alias} named version "
            f"{registered.moved_from} (refine's models, or DVC restored an earlier `train`); "
            f"{models} holds version {registered.version}'s: the alias is moved to it"
        )
    surrogate = load_surrogate(models, params.train.use, registered.path)
    return build_setup(params, surrogate, models_digest(models), registered)


def build_setup(
    params: Params,
    surrogate: Surrogate,
    digest: str,
    registered: RegisteredWeights | None = None,
) -> Setup:
    """A search on ``surrogate`` (whose model directory has ``digest``) with params' settings."""
    ctx = context_of(params)
    problem = TrajectoryProblem(ctx.policy, surrogate, ctx.robot.objectives, ctx.rules)
    note_unconstrained(problem)
    cfg = params.optimize
    settings = search_settings(cfg, params.search_seed)
    initial = initial_population(ctx.policy, cfg, params.sample, params.search_seed)
    return Setup(ctx, problem, settings, initial, digest, registered)


def note_unconstrained(problem: TrajectoryProblem) -> None:
    """Say which physical limits the search cannot see: the surrogate was not trained on them."""
    if problem.unconstrained:
        console.print(
            f"[yellow]the surrogate was not trained on the channels of "
            f"{sorted(problem.unconstrained)} (an acquisition without them): they are not "
            "constrained in the search"
        )


def write_outputs(
    outcome: Outcome, setup: Setup, result: SearchResult, params: Params, to: Outputs
):
    """Front and optimum (one directory, all or nothing), metrics, convergence and figures."""
    from ftfof.report.front import convergence_figure, pcp_figure, star_figure

    names = list(setup.ctx.robot.objectives)
    F, chosen = outcome.evaluation.F, outcome.index
    title = f"{setup.ctx.name}: Pareto front ({len(F)} trajectories)"
    figures = {
        to.star: star_figure(F, names, chosen, title),
        to.pcp: pcp_figure(F, names, chosen, title),
    }
    records = [r.as_dict() for r in result.history]
    write_optimum(to.out, outcome, setup.ctx, setup.models_digest, params.optimize)
    write_metrics("optimize", to.metrics, outcome.summary)
    with atomic_path(to.convergence) as path:
        path.write_text(convergence_csv(records))
    figures[to.convergence.with_suffix(".png")] = convergence_figure(records)
    for target, fig in figures.items():
        save_figure(fig, target)


class OptimizeRun:
    """The stage's MLflow run around the search, the choice and the outputs."""

    def __init__(self, params: Params, setup: Setup):
        self.params, self.setup = params, setup
        self.run_id = ""

    def __enter__(self) -> OptimizeRun:
        params, setup = self.params, self.setup
        experiment = tracking.experiment_name(params.robot)
        mlflow = tracking.setup(experiment)
        digest = setup.models_digest
        link, surrogate_run = tracking.link_tags(
            mlflow,
            experiment,
            "train",
            tracking.MODELS_DIGEST_TAG,
            digest,
            tracking.SURROGATE_RUN_TAG,
            "Surrogates",
            f" (models digest {digest}).",
        )
        if not surrogate_run:
            console.print(
                f"[yellow]no train run with models digest {digest} in this MLflow store; "
                "the optimize run is not linked to one"
            )
        self._context = mlflow.start_run(
            run_name="optimize", tags={**tracking.tags("optimize"), **link}
        )
        run = self._context.__enter__()
        self.mlflow, self.run_id = mlflow, run.info.run_id
        settings = tracking.run_params(
            params,
            optimize=params.optimize.model_dump(),
            objectives=",".join(setup.ctx.robot.objectives),
            free_variables=",".join(setup.ctx.policy.free_names),
            models_digest=digest,
            model=setup.registered.uri,
        )
        mlflow.log_params(settings)
        return self

    def __exit__(self, *exc) -> bool:
        return bool(self._context.__exit__(*exc))

    def search(
        self, on_record: Callable[[ConvergenceRecord], None], to: Outputs
    ) -> tuple[SearchResult, Outcome]:
        """Search (each record also logged as a step), choose, write the outputs, log them."""
        setup = self.setup

        def record(r: ConvergenceRecord) -> None:
            on_record(r)
            self._record(r)

        result = search(setup.problem, setup.settings, setup.initial, record)
        check = simulator_check_of(self.params, setup.ctx)
        outcome = choose(
            self.params.optimize,
            self.params.surface,
            setup.ctx,
            setup.problem,
            result,
            setup.models_digest,
            check,
        )
        write_outputs(outcome, setup, result, self.params, to)
        artifacts = (to.star, to.pcp, to.convergence.with_suffix(".png"), to.convergence)
        self._finish(outcome, artifacts, optimum_digest(to.out))
        return result, outcome

    def _record(self, record: ConvergenceRecord) -> None:
        from mlflow.entities import Metric

        stamp = int(time.time() * 1000)
        step = record.generation
        metrics = [
            Metric(run_metrics.metric_name("search", k), float(getattr(record, k)), stamp, step)
            for k in ("hypervolume", "feasible", "front")
        ]
        self.mlflow.MlflowClient().log_batch(self.run_id, metrics=metrics)

    def _finish(self, outcome: Outcome, artifacts: tuple[Path, ...], optimum_digest: str) -> None:
        mlflow, summary = self.mlflow, outcome.summary
        mlflow.log_metrics(run_metrics.optimize(summary))
        mlflow.log_dict(summary, "optimize.json")
        mlflow.set_tag(tracking.OPTIMUM_DIGEST_TAG, optimum_digest)
        for path in artifacts:
            mlflow.log_artifact(str(path), artifact_path="figures")
