"""The `refine` run: simulate where the optimiser went, train there, search again.

Each round re-simulates the current optimum and front members spread along its front (a resumable
acquisition job), measures the surrogates' fidelity on them *before* training on them, appends them
to the dataset (source ``refine:<k>``, split like the dataset with the round's own seed, so
fine-tuning's early stopping sees the region the optimiser went to), fine-tunes the surrogates
from their weights and re-runs NSGA-II from the previous front. The rounds' clean points are also
candidates beside the surrogate's (docs/optimum.md). It stops after ``refine.rounds`` rounds, or
earlier once the fidelity target on the first-priority objective is met and enough of the round's
points pass the simulator (a front of exploits the surrogate has not seen can rank fs1 well); the
models and optimum that met it are then kept as they are. A round none of whose successful
simulations is new to the training data ends it the same way. What each round decides is
:mod:`ftfof.refine.rounds`; this module reads, simulates, writes and tracks.

``<out>/`` holds one directory per round (``simulations/``, ``models/``, ``optimize/``,
``round.json``) and the final ``models/``, ``optimize/`` and grown ``dataset/`` that `evaluate`
reads. A killed run re-run with the same inputs resumes: finished rounds are kept and a round's
finished simulations are not run again. A run that completed starts afresh, as `acquire` does, so
`dvc repro --force` recomputes.
"""

from __future__ import annotations

import json
import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from ftfof.config import Params
from ftfof.data.acquisition import ACQUISITION
from ftfof.data.refinement import grow
from ftfof.digests import file_sha256, models_digest
from ftfof.errors import DataError
from ftfof.evaluate.run import Inputs, front_sample
from ftfof.evaluate.specs import front_specs
from ftfof.files import atomic_dir, read_table, save_figure, write_json
from ftfof.optimize.select import Nominees
from ftfof.pipeline.artefacts import (
    check_models,
    optimum_digest,
    read_optimum,
    write_optimum,
)
from ftfof.pipeline.bench import bench, context_of
from ftfof.pipeline.console import console
from ftfof.pipeline.jobs import FINAL, Acquisition, close_resumable, open_resumable
from ftfof.pipeline.refine_run import RefineRun
from ftfof.pipeline.summaries import write_metrics
from ftfof.refine import rounds
from ftfof.refine.rounds import Round, Rounds
from ftfof.robot import RobotContext
from ftfof.surrogate.store import FILE, TrainingData, read_dataset, write_dataset

ROUND = "round.json"


@dataclass(frozen=True)
class Paths:
    dataset: Path  # the dataset stage's directory
    acquisition: Path  # the acquire stage's simulations (its clean ones are nominees)
    models: Path  # the train stage's models
    optimize: Path  # the optimize stage's front and optimum
    out: Path  # data/refine
    report: Path  # reports/refine.json
    figure: Path  # fidelity against round (PNG)


@dataclass
class State:
    """What the rounds so far left: the models and front the next round starts from."""

    models: Path
    front: Path
    rounds: Rounds = field(default_factory=Rounds)


def run(params: Params, paths: Paths, workers: int | None = None) -> dict[str, Any]:
    """Refine; write ``paths.out``, the report and its figure; track in MLflow. The report."""
    from ftfof.report.refine import refine_figure

    stage_started = time.perf_counter()
    ctx = context_of(params)
    data = read_dataset(paths.dataset)
    inputs = read_optimum(paths.optimize, ctx.name)
    check_models(inputs, paths.optimize, paths.models)
    if (params.dataset.seq_len, params.dataset.hold) != (data.seq_len, data.hold):
        raise DataError(str(paths.dataset), "was built with other dataset params (re-run it)")
    key = _open(params, paths)
    state = State(paths.models, paths.optimize)
    if params.refine.rounds and params.refine.nominate:  # no search would nominate them
        acquired = read_table(paths.acquisition / FINAL, ACQUISITION, "acquisition")
        state.rounds.measure(rounds.acquired_points(ctx, acquired, params.dataset))
    done_rounds: list[Round] = []
    # the run is open for the rounds: it spans them
    with RefineRun(params, paths.models, paths.optimize, paths.out) as tracked:
        for k in range(1, params.refine.rounds + 1):
            started = time.perf_counter()
            rdir = paths.out / f"round-{k}"
            with tracked.round(k):
                done = _round(params, ctx, rdir, k, key, data, state, workers)
                done.seconds = time.perf_counter() - started
                tracked.round_done({**done.record, "seconds": done.seconds}, rdir)
            done_rounds.append(done)
            console.print(done.line(inputs.objectives[0]))
            if done.last:
                break
        _publish(paths, state, data)
        report = {
            "rounds": [{**r.record, "seconds": round(r.seconds, 2)} for r in done_rounds],
            "seconds": round(time.perf_counter() - stage_started, 2),  # the stage's
        }
        write_metrics("refine", paths.report, report)
        save_figure(refine_figure(report["rounds"], inputs.objectives), paths.figure)
        tracked.finish(report, (paths.report, paths.figure))
    close_resumable(paths.out, key)
    return report


def _open(params: Params, paths: Paths) -> str:
    """The run's fingerprint; ``paths.out`` is kept only to resume an interrupted run of it."""
    identity = {
        "params": params.model_dump(
            exclude={
                "acquire": {"workers", "scheduler", "batch"},
                "polish": True,
                "evaluate": True,
                "logs": True,
            }
        ),
        "dataset": file_sha256(paths.dataset / FILE),
        "models": models_digest(paths.models),
        "optimum": optimum_digest(paths.optimize),
    }
    return open_resumable(paths.out, identity)


def _round(
    params: Params,
    ctx: RobotContext,
    rdir: Path,
    k: int,
    key: str,
    data: TrainingData,
    state: State,
    workers: int | None,
) -> Round:
    """Round ``k`` (or what a finished one left); advances ``state`` unless the round ended the
    refinement."""
    saved = rdir / ROUND
    if saved.exists():
        done = json.loads(saved.read_text())
        if not done["target_met"] and not done["nothing_new"]:
            table = read_table(rdir / "simulations" / FINAL, ACQUISITION, "simulations")
            points = rounds.measured_points(ctx, rounds.successful(table), params.dataset, k)
            new = _rows(params, state.rounds.unseen(table, data.table), k)
            _carry(state, ctx, rdir, points, new)
        return Round(done["record"], done["target_met"], 0, done["nothing_new"])
    from ftfof.surrogate.store import load_surrogate

    inputs = read_optimum(state.front, ctx.name)
    rows = front_sample(inputs, params.refine.points)
    table, simulated = _simulate(params, ctx, rdir / "simulations", inputs, rows, key, k, workers)
    ok = rounds.successful(table)
    points = rounds.measured_points(ctx, ok, params.dataset, k)
    surrogate = load_surrogate(state.models)
    verdict = rounds.judge(
        inputs, ok, table.num_rows, len(points.X), ctx, surrogate, params.refine.target
    )
    unseen = None if verdict.target_met else state.rounds.unseen(table, data.table)
    nothing_new = unseen is not None and rounds.nothing_new(unseen)
    added = 0
    if unseen is not None and not nothing_new:
        new = _rows(params, unseen, k)
        added = new.num_rows
        grown = rounds.grown(data, state.rounds, new, key, k)
        _fine_tune(params, grown, state.models, rdir / "models")

        def search() -> None:  # with the nominees of every round's clean points so far
            nominees = state.rounds.nominees(params.refine.nominate, params.optimize)
            _search(params, ctx, rdir / "models", inputs, rdir / "optimize", nominees)

        _carry(state, ctx, rdir, points, new, search)
    record = rounds.record(k, added, verdict, inputs.objectives)
    write_json(
        saved, {"record": record, "target_met": verdict.target_met, "nothing_new": nothing_new}
    )
    return Round(record, verdict.target_met, simulated, nothing_new)


def _carry(
    state: State,
    ctx: RobotContext,
    rdir: Path,
    points: rounds.Measured,
    new: pa.Table,
    search: Callable[[], None] | None = None,
) -> None:
    """What a round that trained leaves, the same whether it runs now (``search`` once its clean
    ``points`` are candidates) or a resumed run reads it back."""
    state.rounds.measure(points)
    if search is not None:
        search()
    state.rounds.close(rounds.refused_rows(read_optimum(rdir / "optimize", ctx.name)), new)
    state.models, state.front = rdir / "models", rdir / "optimize"


def _rows(params: Params, simulations: pa.Table, k: int) -> pa.Table:
    """A round's simulations as dataset rows."""
    T2 = params.selected_robot.timing.T2
    return rounds.training_rows(simulations, params.dataset, params.base.seed, T2, k)


def _simulate(
    params: Params,
    ctx: RobotContext,
    out: Path,
    inputs: Inputs,
    rows: list[int],
    key: str,
    k: int,
    workers: int | None,
) -> tuple[pa.Table, int]:
    """The round's simulations (optimum and ``rows``), resumed or kept if finished."""
    job_inputs = {"refine": key, "round": k, "optimum": inputs.digest, "front_rows": rows}
    finished = Acquisition.finished(params, ctx, out, job_inputs)
    if finished is not None:
        return finished, 0
    specs, controls = front_specs(bench(params, ctx), inputs, rows)
    job = Acquisition.start(params, ctx, out, specs, controls, job_inputs)
    todo = job.remaining()
    cfg = params.acquire
    n_workers = cfg.workers if workers is None else workers
    wall = job.simulate(todo, n_workers, cfg.scheduler, f"refine round {k}")
    job.finish(wall, len(todo))
    return read_table(out / FINAL, ACQUISITION, "simulations"), len(todo)


def _fine_tune(params: Params, data: TrainingData, start: Path, out: Path) -> None:
    """The ``train.use`` models fine-tuned on ``data`` from the weights in ``start``, and the peak
    models refitted on it (with a local GP on the rounds' rows for ``near_front_peaks``) ->
    ``out``."""
    from ftfof.surrogate.fit import train_all
    from ftfof.surrogate.store import load_states, load_surrogate, write_models

    tune = rounds.fine_tuning(params.train, params.refine)
    states = {loss: s for loss, s in load_states(start).items() if loss == params.train.use}
    run = train_all(
        tune,
        params.search_seed,
        data,
        warm_start=states,
        peaks_from=load_surrogate(start).peaks,
        near_front_peaks=params.refine.near_front_peaks,
    )
    write_models(out, run.results, data, tune, run.peaks)


def _search(
    params: Params,
    ctx: RobotContext,
    models: Path,
    inputs: Inputs,
    out: Path,
    nominees: Nominees | None,
) -> None:
    """The round's search and choice on the fine-tuned ``models`` -> ``out``."""
    from ftfof.pipeline.simcheck import simulator_check_of
    from ftfof.surrogate.store import load_surrogate

    digest = models_digest(models)
    outcome = rounds.search_again(
        ctx,
        load_surrogate(models),
        digest,
        inputs,
        params.optimize,
        params.sample,
        params.search_seed,
        params.refine.generations,
        params.surface,
        simulator_check_of(params, ctx),  # as optimize: the simulator disposes
        nominees,
    )
    write_optimum(out, outcome, ctx, digest, params.optimize)


def _publish(paths: Paths, state: State, data: TrainingData) -> None:
    """The final models, optimum and grown dataset, each directory whole or not at all."""
    for name, source in (("models", state.models), ("optimize", state.front)):
        with atomic_dir(paths.out / name) as tmp:
            for item in sorted(source.iterdir()):
                if item.is_file():
                    shutil.copy(item, tmp / item.name)
    original = paths.dataset / FILE
    if state.rounds.added:
        grown = grow(data.table, state.rounds.added)
        metadata = pq.read_schema(original).metadata
        write_dataset(paths.out / "dataset", grown.replace_schema_metadata(metadata))
    else:
        with atomic_dir(paths.out / "dataset") as tmp:
            shutil.copy(original, tmp / FILE)
