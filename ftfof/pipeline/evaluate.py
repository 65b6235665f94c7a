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
import pandas as pd
import pyarrow.parquet as pq

from ftfof.config import Params
from ftfof.evaluate.feasible import admitted
from ftfof.evaluate.repeat import repeat_specs
from ftfof.evaluate.run import (
    Evaluation,
    Inputs,
    bezier_rows,
    evaluate,
    fidelity_members,
    front_sample,
)
from ftfof.evaluate.specs import evaluation_specs
from ftfof.evaluate.table import moved_row
from ftfof.files import atomic_path
from ftfof.pipeline import tracking
from ftfof.pipeline.artefacts import (
    check_models,
    read_figure,
    read_json,
    read_optimum,
    read_refine,
)
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.catalog import placed
from ftfof.pipeline.console import console
from ftfof.pipeline.jobs import FINAL, Acquisition
from ftfof.pipeline.registry import model_record, promote
from ftfof.pipeline.summaries import write_metrics
from ftfof.report import run_metrics
from ftfof.report.context import STAGE_FIGURES
from ftfof.robot import RobotContext
from ftfof.sim.spec import baseline_specs
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
    robot: Robot  # what the climb, slip and study stages wrote


@dataclass(frozen=True)
class Robot:
    """The robot's stages' outputs the report gathers (:mod:`ftfof.pipeline.catalog`)."""

    climbs: Path  # `ftfof climb`'s climbs (the optimum's traces)
    climb: Path  # its climbing table
    slips: Path  # `ftfof slip`'s climbs (the comparison's figure)
    slip: Path  # its table
    eps: Path  # `ftfof study eps`'s report
    eps_figure: Path

    @classmethod
    def at(cls, reports: Path, data: Path) -> Robot:
        """The catalog's places under ``reports`` and ``data`` (tests use temporary ones)."""
        names = ("climbs_table", "climb_table", "slips", "slip_table")
        return cls(*(placed(n, reports, data) for n in (*names, "eps_study", "eps_study_figure")))


def run(params: Params, paths: Paths, workers: int | None = None) -> Evaluation:
    """Re-simulate the optimum against the common trajectories; report, metrics, export."""
    from ftfof.report.context import evaluation_page
    from ftfof.surrogate.store import load_surrogate

    started = time.perf_counter()
    ctx = context_of(params)
    inputs = read_optimum(paths.optimize, ctx.name)
    check_models(inputs, paths.optimize, paths.models)
    baselines = baseline_trajectories(params, ctx)  # simulated, and judged by the robot's rules
    with _tracked(params, inputs) as mlflow:  # open while it works: the run spans it
        surrogate = load_surrogate(paths.models)
        pictures = {key: read_figure(paths.figures / key) for key, _ in STAGE_FIGURES}
        rounds = read_refine(paths.refine)
        robot = gathered(paths.robot)  # the robot's stages, read before anything runs
        simulations = _simulated(params, ctx, paths.out, inputs, baselines, workers)
        bezier = bezier_rows(ctx, inputs)
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
            moved_row(robot.summary["climb"]),
        )
        result.summary.update(robot.summary)
        html = evaluation_page(
            result,
            ctx,
            inputs,
            params.surface,
            params.climb.steps,
            pictures,
            robot.figures,
            str(paths.export),
            rounds,
            robot.scenario,
        )
        _export(result, paths.export)
        result.summary["seconds"] = round(time.perf_counter() - started, 2)  # the stage's time
        result.summary["model"] = model_record(paths.models)  # the surrogates that found it
        write_metrics("evaluate", paths.metrics, result.summary)
        with atomic_path(paths.report) as tmp:
            tmp.write_text(html, encoding="utf-8")
        _log(mlflow, params, result.summary, paths)
    return result


def _simulated(
    params: Params,
    ctx: RobotContext,
    out: Path,
    inputs: Inputs,
    baselines: Mapping[str, Sampled],
    workers: int | None,
) -> pd.DataFrame:
    """The evaluation's simulations (:func:`_job`), those still to run run now in a pool of
    ``workers`` (None: acquire.workers)."""
    cfg, acquire = params.evaluate, params.acquire
    front_rows = front_sample(inputs, cfg.front_points)
    job = _job(params, ctx, out, inputs, front_rows, baselines)
    todo = job.remaining()
    console.print(
        f"evaluate {ctx.name} on {params.surface}: {len(job.specs)} simulations "
        f"(optimum, {len(front_rows)} front members, baselines"
        f"{'; Table I again at the check step' if cfg.check_step else ''}"
        f"{'; all on the check film' if cfg.check_nodes else ''}"
        f"{'; the front twice more, each off by the repeatability' if cfg.repeat_front else ''}), "
        f"{len(todo)} to run"
    )
    workers = acquire.workers if workers is None else workers
    wall = job.simulate(todo, workers, acquire.scheduler, "evaluate")
    job.finish(wall, len(todo))
    return pq.read_table(job.out / FINAL).to_pandas()


def _export(result: Evaluation, path: Path) -> None:
    """The optimum for a controller, as CSV."""
    controller = result.controller
    with atomic_path(path) as tmp:
        header = ",".join(controller.columns)
        np.savetxt(tmp, controller.table, delimiter=",", header=header, comments="", fmt="%.9g")


@dataclass(frozen=True)
class Gathered:
    summary: dict[str, Any]  # climb, slip (where it ran) and eps_study, as metrics.json keeps them
    figures: dict[str, str]  # the optimum's climb and the slip comparison, as data URIs
    scenario: dict[str, Any]  # evaluate.slip_scenario as the slip stage ran it


def gathered(at: Robot) -> Gathered:
    """The climb, slip and study stages' outputs for the report; one missing names the command
    that writes it."""
    climb = read_json(at.climb)
    slip = read_json(at.slip)
    summary: dict[str, Any] = {"climb": climb}
    figures = {}
    if "optimum" in climb:
        figures["climb_traces"] = read_figure(at.climbs / "optimum.png")
        figures["climb_side"] = read_figure(at.climbs / "optimum_side.png")
    if slip["slip"] is not None:
        summary["slip"] = slip["slip"]
        figures["slip"] = read_figure(at.slips / slip["figure"])
    summary["eps_study"] = read_json(at.eps)
    figures["eps_study"] = read_figure(at.eps_figure)
    return Gathered(summary, figures, slip["scenario"])


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
    if cfg.repeat_front:
        members = fidelity_members(inputs, front_rows)
        error = params.optimize.verify_repeatability
        repeats, repeat_controls = repeat_specs(on, ctx.policy, members, error, params.base.seed)
        specs, controls = specs + repeats, controls | repeat_controls
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
            "repeat_front": cfg.repeat_front,
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
