"""The `evaluate` run: read what `optimize` left, re-simulate it as a resumable job, evaluate,
write the report, and track it in MLflow linked to the optimize run."""

from __future__ import annotations

import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq

from ftfof.config import Params
from ftfof.evaluate.feasible import admitted, climbable
from ftfof.evaluate.run import Evaluation, Inputs, decision, evaluate, front_sample
from ftfof.evaluate.runs import PAPER_OPTIMUM, table_name
from ftfof.evaluate.specs import evaluation_specs
from ftfof.evaluate.table import climb_record
from ftfof.files import atomic_path
from ftfof.pipeline import tracking
from ftfof.pipeline.artefacts import (
    check_models,
    read_figure,
    read_optimum,
    read_refine,
)
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.climb import (
    CLIMBS,
    climb_all,
    slip_comparison,
    slip_name,
    slip_scenario_spec,
    spec_for,
)
from ftfof.pipeline.console import console
from ftfof.pipeline.jobs import FINAL, Acquisition
from ftfof.pipeline.registry import model_record, promote
from ftfof.pipeline.summaries import write_metrics
from ftfof.report import run_metrics
from ftfof.report.context import STAGE_FIGURES
from ftfof.robot import RobotContext
from ftfof.sim.spec import baseline_specs
from ftfof.study.eps import simulate as eps_study
from ftfof.trajectory.piecewise import Sampled


@dataclass(frozen=True)
class Paths:
    optimize: Path  # the optimum and its front (what `refine` passed on)
    models: Path
    figures: Path  # where the train/optimize/refine PNGs are
    out: Path  # the simulations of this evaluation
    report: Path
    metrics: Path
    export: Path
    refine: Path  # reports/refine.json


def run(params: Params, paths: Paths, workers: int | None = None) -> Evaluation:
    """Re-simulate the optimum against the common trajectories; report, metrics, export."""
    from ftfof.report.context import evaluation_page
    from ftfof.surrogate.store import load_surrogate

    started = time.perf_counter()
    ctx = context_of(params)
    inputs = read_optimum(paths.optimize, ctx.name)
    check_models(inputs, paths.optimize, paths.models)
    baselines = baseline_trajectories(params, ctx)  # simulated, and judged by the robot's rules
    scenario = params.evaluate.slip_scenario
    slip = None  # the slip comparison's climb, checked before anything runs
    if params.evaluate.slip_comparison and ctx.robot.climber is not None:
        slip = slip_scenario_spec(params, ctx, baselines[scenario.trajectory])
    with _tracked(params, inputs) as mlflow:  # open while it works: the run spans it
        surrogate = load_surrogate(paths.models)
        pictures = {key: read_figure(paths.figures / key) for key, _ in STAGE_FIGURES}
        rounds = read_refine(paths.refine)
        front_rows = front_sample(inputs, params.evaluate.front_points)
        job = _job(params, ctx, paths.out, inputs, front_rows, baselines)
        cfg = params.acquire
        todo = job.remaining()
        console.print(
            f"evaluate {ctx.name} on {params.surface}: {len(job.specs)} simulations "
            f"(optimum, {len(front_rows)} front members, baselines"
            f"{'; Table I again at the check step' if params.evaluate.check_step else ''}"
            f"{'; all on the check film' if params.evaluate.check_nodes else ''}), "
            f"{len(todo)} to run"
        )
        pool = cfg.workers if workers is None else workers
        wall = job.simulate(todo, pool, cfg.scheduler, "evaluate")
        job.finish(wall, len(todo))
        simulations = pq.read_table(job.out / FINAL).to_pandas()
        bezier = {"optimum": decision(inputs, inputs.optimum["front_row"])}
        if ctx.robot.published_optimum is not None:
            bezier[table_name(PAPER_OPTIMUM)] = np.asarray(ctx.robot.published_optimum)
        breaks = admitted(ctx, baselines, bezier)
        result = evaluate(
            params.evaluate,
            params.acquire.solver,
            params.surface,
            ctx,
            inputs,
            simulations,
            surrogate,
            breaks,
        )
        climbed = _climbs(params, ctx, paths.out, baselines, bezier, breaks, workers)
        result.summary["climb"] = climbed
        figures = _climb_figures(paths.out, climbed)
        if slip is not None:
            out = paths.out / CLIMBS / "slip"
            result.summary["slip"] = slip_comparison(*slip, out, pool)
            figures["slip"] = read_figure(out / f"{slip_name(scenario)}.controllers.png")
        eps = eps_study(bench(params, ctx), baselines["eps_bezier"], params.study.eps, pool)
        result.summary["eps_study"] = eps.report()
        html = evaluation_page(
            result,
            ctx,
            inputs,
            params.surface,
            params.climb.steps,
            pictures,
            figures,
            eps,
            str(paths.export),
            rounds,
            scenario.model_dump(),
        )
        controller = result.controller
        with atomic_path(paths.export) as tmp:
            header = ",".join(controller.columns)
            np.savetxt(tmp, controller.table, delimiter=",", header=header, comments="", fmt="%.9g")
        result.summary["seconds"] = round(time.perf_counter() - started, 2)  # the stage's time
        result.summary["model"] = model_record(paths.models)  # the surrogates that found it
        write_metrics("evaluate", paths.metrics, result.summary)
        with atomic_path(paths.report) as tmp:
            tmp.write_text(html, encoding="utf-8")
        _log(mlflow, params, result.summary, paths)
    return result


def _climbs(
    params: Params,
    ctx: RobotContext,
    out: Path,
    baselines: Mapping[str, Sampled],
    bezier: Mapping[str, np.ndarray],
    breaks: Mapping[str, list[str]],
    workers: int | None,
) -> dict[str, Any]:
    """Table I's trajectories on the climbing robot, each one the robot can run
    (:func:`ftfof.evaluate.feasible.climbable`): per name its climb's summary and fall
    (:func:`ftfof.evaluate.table.climb_record`)."""
    if not params.evaluate.climb or ctx.robot.climber is None:
        return {}
    runnable, skipped = climbable(ctx, baselines, bezier, breaks)
    specs = {n: spec_for(params, ctx, n, t, X) for n, (t, X) in runnable.items()}
    console.print(f"evaluate: the climbing robot climbs {', '.join(specs)}")
    cfg = params.acquire
    docs = climb_all(params, specs, out / CLIMBS, cfg.workers if workers is None else workers)
    return climb_record(docs, skipped)


def _climb_figures(out: Path, climbed: Mapping[str, Any]) -> dict[str, str]:
    """The optimum's climb, as traces and from the side, for the report."""
    if "optimum" not in climbed:
        return {}
    return {
        "climb_traces": read_figure(out / CLIMBS / "optimum.png"),
        "climb_side": read_figure(out / CLIMBS / "optimum_side.png"),
    }


def _job(
    params: Params,
    ctx: RobotContext,
    out: Path,
    inputs: Inputs,
    front_rows: list[int],
    baselines: Mapping[str, Sampled],
) -> Acquisition:
    """The evaluation's simulations (:func:`ftfof.evaluate.specs.evaluation_specs`), resumable
    under ``out``."""
    on = bench(params, ctx)
    cfg = params.evaluate
    specs, controls = evaluation_specs(
        on,
        inputs,
        front_rows,
        baseline_specs(on, baselines),
        ctx.robot.published_optimum,
        cfg.check_step,
        cfg.check_nodes,
    )
    return Acquisition.start(
        params,
        ctx,
        out,
        specs,
        controls,
        {
            "optimum": inputs.digest,
            "front_rows": front_rows,
            "check_step": cfg.check_step,  # a resumed job keeps runs of one step
            "check_nodes": cfg.check_nodes,  # and of one film
        },
    )


@contextmanager
def _tracked(params: Params, inputs: Inputs) -> Iterator[Any]:
    """The `evaluate` run, open while the stage works, linked to the run that wrote its optimum
    (`polish`; `refine` or `optimize` when evaluate is pointed at their output)."""
    experiment = tracking.experiment_name(params.robot)
    mlflow = tracking.setup(experiment)
    for source in ("polish", "refine", "optimize"):  # the run that wrote the optimum
        link, found = tracking.link_tags(
            mlflow,
            experiment,
            source,
            tracking.OPTIMUM_DIGEST_TAG,
            inputs.digest,
            tracking.OPTIMIZE_RUN_TAG,
            "Optimum",
        )
        if found:
            break
    with mlflow.start_run(run_name="evaluate", tags={**tracking.tags("evaluate"), **link}):
        mlflow.log_params(tracking.run_params(params, evaluate=params.evaluate.model_dump()))
        yield mlflow


def _log(mlflow, params: Params, summary: dict, paths: Paths) -> None:
    """The table and fidelity as metrics, the report as artifacts; ``train.alias`` moved to the
    model version that found the optimum, which the run is tagged with."""
    mlflow.log_metrics(run_metrics.evaluate(summary))
    for path in (paths.report, paths.export, paths.metrics):
        mlflow.log_artifact(str(path), artifact_path="report")
    version = promote(
        mlflow, params.robot, summary["model"]["loss"], params.train.alias, paths.models
    )
    if version is None:
        console.print(
            f"[yellow]no registered model version holds {paths.models}'s surrogates: "
            f"{params.train.alias} is not moved"
        )
    mlflow.set_tag(tracking.MODEL_TAG, version.uri if version else "unregistered")
