"""The `evaluate` run: read what `optimize` left, re-simulate it as a resumable job, evaluate,
write the report, and track it in MLflow linked to the optimize run."""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq

from ftfof.config import Params
from ftfof.digests import models_digest, optimum_digest
from ftfof.errors import DataError
from ftfof.evaluate.film_check import FILM
from ftfof.evaluate.run import (
    OPTIMUM,
    PAPER_OPTIMUM,
    PARETO,
    REFINEMENT,
    TRAINING,
    Evaluation,
    Inputs,
    decision,
    evaluate,
    front_sample,
)
from ftfof.evaluate.step_check import FINE
from ftfof.files import atomic_path, write_json
from ftfof.pipeline import tracking
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench, context_of
from ftfof.pipeline.console import console
from ftfof.pipeline.jobs import FINAL, Acquisition
from ftfof.robot import RobotContext
from ftfof.sim.spec import Bench, SampleSpec


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
    from ftfof.report.html import render
    from ftfof.surrogate.store import load_surrogate

    started = time.perf_counter()
    ctx = context_of(params)
    inputs = read_inputs(paths.optimize, ctx.name)
    check_models(inputs, paths.optimize, paths.models)
    surrogate = load_surrogate(paths.models)
    pictures = {key: _picture(paths.figures / key) for key, _ in (*PARETO, *TRAINING, *REFINEMENT)}
    rounds = read_refine(paths.refine)
    front_rows = front_sample(inputs, params.evaluate.front_points)
    job = _job(params, ctx, paths.out, inputs, front_rows)
    cfg = params.acquire
    todo = job.remaining()
    console.print(
        f"evaluate {ctx.name} on {params.surface}: {len(job.specs)} simulations "
        f"(optimum, {len(front_rows)} front members, baselines"
        f"{'; Table I again at the check step' if params.evaluate.check_step else ''}"
        f"{'; all on the check film' if params.evaluate.check_nodes else ''}), "
        f"{len(todo)} to run"
    )
    wall = job.simulate(
        todo, cfg.workers if workers is None else workers, cfg.scheduler, "evaluate"
    )
    job.finish(wall, len(todo))
    simulations = pq.read_table(job.out / FINAL).to_pandas()
    result = evaluate(params, ctx, inputs, simulations, surrogate)
    pictures.update(result.figures)
    extra = {"figures": pictures, "export_path": str(paths.export), "refine": rounds}
    html = render({**result.context, **extra})
    controller = result.controller
    with atomic_path(paths.export) as tmp:
        header = ",".join(controller.columns)
        np.savetxt(tmp, controller.table, delimiter=",", header=header, comments="", fmt="%.9g")
    result.summary["seconds"] = round(time.perf_counter() - started, 2)  # the stage's time
    write_json(paths.metrics, result.summary)
    with atomic_path(paths.report) as tmp:
        tmp.write_text(html, encoding="utf-8")
    _track(params, inputs, result.summary, (paths.report, paths.export, paths.metrics))
    return result


# What a stage reads from an optimum.json (dotted: inside a section). A file from an older
# ftfof that lacks one is refused by name, not with a KeyError deep in the stage.
POLISH_READS = ("robot", "front_row", "models_digest", "simulator_check")
EVALUATE_READS = (*POLISH_READS, "origin", "decision", "rhs.rows", "rhs.steps")


def missing_fields(record: dict[str, Any], fields: Sequence[str]) -> list[str]:
    """Those of ``fields`` that ``record`` lacks."""

    def present(path: str) -> bool:
        node: Any = record
        for key in path.split("."):
            if not isinstance(node, dict) or key not in node:
                return False
            node = node[key]
        return True

    return [f for f in fields if not present(f)]


def read_inputs(directory: Path, robot: str, fields: Sequence[str] = EVALUATE_READS) -> Inputs:
    """The optimum and its front, checked to be of ``robot`` and to hold ``fields``; any problem
    is one DataError."""
    path = directory / "optimum.json"
    if not path.exists() or not (directory / "front.parquet").exists():
        raise DataError(str(directory), "no optimum (run `ftfof optimize` first)")
    try:
        optimum = json.loads(path.read_text())
        front = pq.read_table(directory / "front.parquet")
        meta = json.loads(front.schema.metadata[b"ftfof"])
    except (ValueError, KeyError, OSError) as err:
        raise DataError(str(directory), f"unreadable optimize output ({err})") from None
    missing = missing_fields(optimum, fields)
    if missing:
        raise DataError(
            str(path),
            f"lacks {', '.join(missing)}: written by an older ftfof (re-run `ftfof optimize`)",
        )
    if optimum.get("robot") != robot or meta.get("robot") != robot:
        raise DataError(
            str(directory),
            f"holds an optimum for {optimum.get('robot')!r} but params select {robot!r} "
            "(re-run `ftfof optimize`)",
        )
    frame = front.to_pandas().set_index("row")
    return Inputs(optimum, frame, list(meta["objectives"]), optimum_digest(directory))


def read_refine(path: Path) -> list[dict]:
    """The rounds of reports/refine.json (empty with ``refine.rounds: 0``)."""
    if not path.exists():
        raise DataError(str(path), "no refinement report (run `ftfof refine` first)")
    try:
        return list(json.loads(path.read_text())["rounds"])
    except (ValueError, KeyError, TypeError) as err:
        raise DataError(str(path), f"unreadable refinement report ({err})") from None


def check_models(inputs: Inputs, directory: Path, models: Path) -> None:
    """The optimum in ``directory`` must have been found on the surrogates in ``models``."""
    if inputs.optimum["models_digest"] != models_digest(models):
        raise DataError(str(directory), f"was optimised on other models than {models} (re-run it)")


def _picture(path: Path) -> str:
    from ftfof.report.html import png_data_uri

    if not path.exists():
        raise DataError(str(path), "figure missing (run the stage that writes it)")
    try:
        return png_data_uri(path.read_bytes())
    except ValueError:
        raise DataError(str(path), "is not a PNG image") from None


def _job(
    params: Params, ctx: RobotContext, out: Path, inputs: Inputs, front_rows: list[int]
) -> Acquisition:
    """The optimum, the sampled front rows and the baselines; Table I's trajectories again at
    ``evaluate.check_step`` (sources prefixed ``FINE``), and all of them again on
    ``evaluate.check_nodes`` film elements (prefixed ``FILM``); resumable under ``out``."""
    on = bench(params, ctx)
    specs, controls = front_specs(on, inputs, front_rows)
    specs += baseline_specs(on, baseline_trajectories(params, ctx))
    if ctx.robot.published_optimum is not None:  # held out: simulated, never fitted
        X = np.asarray(ctx.robot.published_optimum, dtype=float)
        spec = on.bezier(PAPER_OPTIMUM, 0, X)
        specs.append(spec)
        controls[spec.key] = X
    cfg = params.evaluate
    variants = []
    if cfg.check_step is not None:
        variants += [with_step(s, cfg.check_step) for s in specs if s.source != "front"]
    if cfg.check_nodes is not None:
        variants += [with_nodes(s, cfg.check_nodes) for s in specs]
    for variant in variants:
        original = variant.key.removeprefix(FINE).removeprefix(FILM)
        if original in controls:
            controls[variant.key] = controls[original]
    specs += variants
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


def with_step(spec: SampleSpec, step: float) -> SampleSpec:
    """``spec`` simulated with every solver step ``step`` (a change of step within a run
    disturbs the body), its source and key prefixed ``FINE`` (the same sensor-noise seed)."""
    return _variant(spec, FINE, step=step, free_step=step)


def with_nodes(spec: SampleSpec, nodes: int) -> SampleSpec:
    """``spec`` on a film of ``nodes`` elements, its source and key prefixed ``FILM``."""
    return _variant(spec, FILM, nodes=nodes)


def _variant(spec: SampleSpec, prefix: str, **solver: float) -> SampleSpec:
    """``spec`` with ``solver`` settings changed, its source and key prefixed ``prefix``."""
    changed = spec.solver.model_copy(update=solver)
    return replace(spec, key=prefix + spec.key, source=prefix + spec.source, solver=changed)


def front_specs(
    on: Bench, inputs: Inputs, front_rows: list[int]
) -> tuple[list[SampleSpec], dict[str, np.ndarray]]:
    """Specs of the optimum (source ``optimum``) and of ``front_rows`` (source ``front``), each
    with its front row as sample id, and their decision vectors by key."""
    chosen = inputs.optimum["front_row"]
    specs, controls = [], {}
    for source, row in [(OPTIMUM, chosen), *(("front", r) for r in front_rows)]:
        X = decision(inputs, row)
        spec = on.bezier(source, row, X)
        specs.append(spec)
        controls[spec.key] = X
    return specs, controls


def _track(params: Params, inputs: Inputs, summary: dict, artifacts: tuple[Path, ...]) -> None:
    """An `evaluate` run with the table and fidelity as metrics, linked to the run that wrote its
    optimum (`polish`; `refine` or `optimize` when evaluate is pointed at their output)."""
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
    metrics = {
        f"{name}.{key}": value
        for name, row in summary["table"].items()
        for key, value in row.items()
    }
    for objective, values in summary["fidelity"].items():
        for key, value in values.items():
            if value == value:  # MLflow rejects NaN
                metrics[f"fidelity.{objective}.{key}"] = float(value)
    with mlflow.start_run(run_name="evaluate", tags={**tracking.tags("evaluate"), **link}):
        settings = {
            "evaluate": params.evaluate.model_dump(),
            "robot": params.robot,
            "surface": params.surface,
        }
        mlflow.log_params(tracking.flatten(settings))
        mlflow.log_metrics(metrics)
        for path in artifacts:
            mlflow.log_artifact(str(path), artifact_path="report")
