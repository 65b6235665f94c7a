"""The `refine` run: simulate where the optimiser went, train there, search again.

Each round re-simulates the current optimum and front members spread along its front (a resumable
acquisition job), measures the surrogates' fidelity on them *before* training on them, appends them
to the dataset (source ``refine:<k>``, split like the dataset with the round's own seed, so
fine-tuning's early stopping sees the region the optimiser went to), fine-tunes the surrogates
from their weights and re-runs NSGA-II from the previous front. The rounds' clean points are also
candidates: the best of them (:func:`nominees_of`) join each round's simulator check beside the
surrogate's and may be chosen (docs/optimum.md). It stops after ``refine.rounds``
rounds, or earlier once the fidelity target on the first-priority objective is met and enough of
the round's points pass the simulator (the pad lets go, its film survives, it lands: a front of
exploits the surrogate has not seen can rank fs1 well); the models and optimum that met it are
then kept as they are. A round none of whose successful simulations is new to the training data
ends it the same way: there is nothing to fine-tune on.

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
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from ftfof.config import Optimize, Params, RefineTarget
from ftfof.data import dataset as ds
from ftfof.data import targets
from ftfof.data.acquisition import ACQUISITION
from ftfof.data.refinement import grow, round_rows
from ftfof.digests import file_sha256, json_sha256, models_digest
from ftfof.errors import DataError, SimulationError
from ftfof.evaluate.fidelity import Fidelity, relative_error, simulated_objectives, target_met
from ftfof.evaluate.run import (
    OPTIMUM,
    Inputs,
    channels,
    fidelity_of,
    from_front,
    front_sample,
    judged_front,
    simulated_rows,
)
from ftfof.evaluate.specs import front_specs
from ftfof.files import atomic_dir, read_table, save_figure, write_json
from ftfof.optimize.select import FRONT, Nominees, rhs_ranking
from ftfof.pipeline import tracking
from ftfof.pipeline.artefacts import (
    check_models,
    optimum_digest,
    read_optimum,
    refused_rows,
    write_optimum,
)
from ftfof.pipeline.bench import bench, context_of
from ftfof.pipeline.console import console
from ftfof.pipeline.jobs import FINAL, Acquisition, close_resumable, open_resumable
from ftfof.robot import RobotContext
from ftfof.seeds import seed_for
from ftfof.surrogate.store import FILE, TrainingData, read_dataset, write_dataset
from ftfof.trajectory.bezier import DECISION_NAMES, same_trajectory

ROUND = "round.json"
DIGITS = 6  # of the fidelity numbers in round.json and the report


@dataclass(frozen=True)
class Paths:
    dataset: Path  # the dataset stage's directory
    models: Path  # the train stage's models
    optimize: Path  # the optimize stage's front and optimum
    out: Path  # data/refine
    report: Path  # reports/refine.json
    figure: Path  # fidelity against round (PNG)


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


@dataclass(frozen=True)
class Measured:
    """A round's clean simulated points (the pad let go, the film survived, the foot landed, the
    body stayed within its limit): decision rows (m) and their objectives from the simulated
    forces, in priority order."""

    X: np.ndarray
    F: np.ndarray
    origin: str  # refine:<round>


@dataclass
class State:
    """What the rounds so far left: the models and front the next round starts from."""

    models: Path
    front: Path
    added: list[pa.Table] = field(default_factory=list)  # each round's training rows
    measured: list[Measured] = field(default_factory=list)  # each round's clean points
    # decision rows the simulator check refused in a round: never nominated again (fresh copies
    # would give a refused trajectory another draw)
    refused: list[np.ndarray] = field(default_factory=lambda: [np.empty((0, len(DECISION_NAMES)))])


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
    rounds: list[Round] = []
    for k in range(1, params.refine.rounds + 1):
        started = time.perf_counter()
        done = _round(params, ctx, paths.out / f"round-{k}", k, key, data, state, workers)
        done.seconds = time.perf_counter() - started
        rounds.append(done)
        _say(done, inputs.objectives[0])
        if done.last:
            break
    _publish(paths, state, data)
    report = {
        "rounds": [{**r.record, "seconds": round(r.seconds, 2)} for r in rounds],
        "seconds": round(time.perf_counter() - stage_started, 2),  # the stage's, as in the rest
    }
    write_json(paths.report, report)
    save_figure(refine_figure(report["rounds"], inputs.objectives), paths.figure)
    _track(params, paths, report["rounds"], (paths.report, paths.figure))
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
    """Round ``k`` (or what a finished one left); advances ``state`` unless the target was met."""
    saved = rdir / ROUND
    if saved.exists():
        done = json.loads(saved.read_text())
        if not done["target_met"] and not done["nothing_new"]:
            table = read_table(rdir / "simulations" / FINAL, ACQUISITION, "simulations")
            state.measured.append(_measured(params, ctx, _ok(table), k))
            state.refused.append(_refused(rdir / "optimize", ctx.name))
            _advance(state, rdir, _rows(params, _unseen(table, [data.table, *state.added]), k))
        return Round(done["record"], done["target_met"], 0, done["nothing_new"])
    from ftfof.surrogate.store import load_surrogate

    inputs = read_optimum(state.front, ctx.name)
    rows = front_sample(inputs, params.refine.points)
    table, simulated = _simulate(params, ctx, rdir / "simulations", inputs, rows, key, k, workers)
    ok = _ok(table)
    fid, predicted, measured = fidelity_of(inputs, ok, ctx, load_surrogate(state.models))
    names = inputs.objectives
    measured_points = _measured(params, ctx, ok, k)
    clean = len(measured_points.X) / table.num_rows  # a failed run is not clean
    # a nominee optimum is among the training rows: its error says nothing, the front's does
    first = fid[0].median_relative_error
    optimum_error = relative_error(predicted[0, 0], measured[0, 0]) if from_front(inputs) else first
    met = round_target_met(params.refine.target, fid[0], optimum_error, clean)
    unseen = None if met else _unseen(table, [data.table, *state.added])
    nothing_new = unseen is not None and "ok" not in unseen.column("status").to_pylist()
    added = 0
    if unseen is not None and not nothing_new:
        new = _rows(params, unseen, k)
        added = new.num_rows
        grown = TrainingData(
            grow(data.table, [*state.added, new]),
            data.normalization,
            data.seq_len,
            data.hold,
            json_sha256({"dataset": data.metadata_digest, "refine": key, "round": k}, 16),
        )
        _fine_tune(params, grown, state.models, rdir / "models")
        state.measured.append(measured_points)
        nominees = nominees_of(
            state.measured, params.refine.nominate, params.optimize, np.vstack(state.refused)
        )
        _search(params, ctx, rdir / "models", inputs, rdir / "optimize", nominees)
        state.refused.append(_refused(rdir / "optimize", ctx.name))
        _advance(state, rdir, new)
    record = _record(k, added, fid, clean, names, predicted[0], measured[0])
    write_json(saved, {"record": record, "target_met": met, "nothing_new": nothing_new})
    return Round(record, met, simulated, nothing_new)


def _measured(params: Params, ctx: RobotContext, ok, k: int) -> Measured:
    """Round ``k``'s successful simulations a real foot could run, with their simulated
    objectives (binned as the surrogate's targets, as the simulator check computes them)."""
    sims = simulated_rows(ok)
    clean = np.array([m["clean"] for m in judged_front(ctx, ok)["members"]], dtype=bool)
    sims = sims[clean]
    X = sims[list(DECISION_NAMES)].to_numpy(dtype=float)
    names = ctx.robot.objectives
    F = np.empty((0, len(names)))
    if len(sims):
        d = params.dataset
        force_t = targets.time_base(ctx.policy.timing.T3, d.hold, d.seq_len)
        runs = [channels(r) for _, r in sims.iterrows()]
        F = simulated_objectives(
            names, ctx.policy, X, runs, force_t, d.hold, ctx.robot.pre_pressure
        )
    return Measured(X, F, f"refine:{k}")


def nominees_of(
    measured: list[Measured], limit: int, cfg: Optimize, refused: np.ndarray | None = None
) -> Nominees | None:
    """The first ``limit`` of the rounds' clean points: the pool's non-dominated layers on the
    robot's first two priorities (MST-M3F: pull and body jitter), in RHS order (``cfg``'s alpha
    and beta, on every simulated objective) within a layer. RHS's alpha cut presumes a front:
    over the whole pool, whose pull runs up to 12 N, its first cut kept pulls to 8 N. A front
    of all objectives would not help: nearly every point is best at one of six. A trajectory
    simulated in several rounds counts once, with its first round's values; one the simulator
    check ``refused`` (decision rows) is left out, as is one with a non-finite objective. None
    when there are none."""
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


def _unseen(rows: pa.Table, tables: list[pa.Table]) -> pa.Table:
    """``rows`` but those whose trajectory (decision values) a table already holds: a nominee
    optimum is re-simulated in the next round, and is in the training data already (the same
    trajectory in both splits would leak into early stopping)."""
    names = list(DECISION_NAMES)
    seen = np.vstack([t.select(names).to_pandas().to_numpy(float) for t in tables])
    new = rows.select(names).to_pandas().to_numpy(float)
    return rows.filter(pa.array(~same_trajectory(new, seen)))


def _refused(optimize: Path, robot: str) -> np.ndarray:
    """The decision rows the round's simulator check refused."""
    return refused_rows(read_optimum(optimize, robot))


def round_target_met(
    target: RefineTarget, first: Fidelity, optimum_error: float, clean: float
) -> bool:
    """Whether a round's points end the refinement: the first priority's fidelity (and the
    relative error at the optimum) meets the target, and enough of the points are clean."""
    fidelity_met = target_met(first, optimum_error, target.spearman, target.relative_error)
    return fidelity_met and clean >= target.clean


def _record(
    k: int, added: int, fid: list[Fidelity], clean: float, names: list[str], predicted, simulated
) -> dict[str, Any]:
    """A round's entry of reports/refine.json, but the seconds."""

    def by_name(values) -> dict[str, float]:
        return {n: round(float(v), DIGITS) for n, v in zip(names, values, strict=True)}

    return {
        "round": k,
        "added": added,
        "clean_fraction": clean,
        "fidelity": {
            f.objective: {
                "mae": round(f.mean_abs_error, DIGITS),
                "median_relative_error": round(f.median_relative_error, DIGITS),
                "spearman": round(f.spearman, DIGITS),
            }
            for f in fid
        },
        "optimum": {"predicted": by_name(predicted), "simulated": by_name(simulated)},
    }


def _advance(state: State, rdir: Path, rows: pa.Table) -> None:
    state.models, state.front = rdir / "models", rdir / "optimize"
    state.added.append(rows)


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


def _ok(table: pa.Table):
    """The successful simulations as a DataFrame; the optimum's must be among them."""
    df = table.to_pandas()
    optimum = df[df.source == OPTIMUM]
    if optimum.empty or optimum.iloc[0].status != "ok":
        error = optimum.iloc[0].error if not optimum.empty else "missing"
        raise SimulationError(OPTIMUM, f"re-simulation failed: {error}")
    return df[df.status == "ok"]


def _rows(params: Params, table: pa.Table, k: int) -> pa.Table:
    """A round's successful simulations as dataset rows, some held out for validation."""
    seed = seed_for(params.base.seed, "split", k)  # each round its own held-out positions
    built, _ = ds.build(table, params.dataset, seed, params.selected_robot.timing.T2)
    return round_rows(built, k)


def _fine_tune(params: Params, data: TrainingData, start: Path, out: Path) -> None:
    """The ``train.use`` models fine-tuned on ``data`` from the weights in ``start``, and the peak
    models refitted on it (with a local GP on the rounds' rows for ``near_front_peaks``) ->
    ``out``."""
    from ftfof.surrogate.fit import train_all
    from ftfof.surrogate.store import load_states, load_surrogate, write_models

    cfg = params.refine
    tune = params.train.model_copy(
        update={
            "losses": [params.train.use],
            "epochs": cfg.epochs,
            "patience": cfg.patience,
            "lr": cfg.lr,
        }
    )
    states = {loss: s for loss, s in load_states(start).items() if loss == params.train.use}
    peaks = load_surrogate(start).peaks
    run = train_all(
        tune,
        params.search_seed,
        data,
        warm_start=states,
        peaks_from=peaks,
        near_front_peaks=cfg.near_front_peaks,
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
    """NSGA-II on the fine-tuned ``models`` from the previous front, then RHS with the simulator's
    check, as `optimize` chooses, the ``nominees`` among the candidates -> ``out``."""
    from ftfof.optimize.problem import TrajectoryProblem
    from ftfof.optimize.search import search
    from ftfof.optimize.select import choose
    from ftfof.optimize.setup import initial_population, search_settings
    from ftfof.pipeline.simcheck import simulator_check_of
    from ftfof.surrogate.store import load_surrogate

    cfg, digest = params.optimize, models_digest(models)
    problem = TrajectoryProblem(ctx.policy, load_surrogate(models), ctx.robot.objectives, ctx.rules)
    members = inputs.front[inputs.front.origin == FRONT]  # nominees are not of the front
    front = members[list(DECISION_NAMES)].to_numpy(dtype=float)
    initial = initial_population(ctx.policy, cfg, params.sample, params.search_seed, front)
    settings = search_settings(cfg, params.search_seed, params.refine.generations)
    result = search(problem, settings, initial)
    check = simulator_check_of(params, ctx)  # as optimize: the simulator disposes
    outcome = choose(cfg, params.surface, ctx, problem, result, digest, check, nominees)
    write_optimum(out, outcome, ctx, digest, cfg)


def _publish(paths: Paths, state: State, data: TrainingData) -> None:
    """The final models, optimum and grown dataset, each directory whole or not at all."""
    for name, source in (("models", state.models), ("optimize", state.front)):
        with atomic_dir(paths.out / name) as tmp:
            for item in sorted(source.iterdir()):
                if item.is_file():
                    shutil.copy(item, tmp / item.name)
    original = paths.dataset / FILE
    if state.added:
        grown = grow(data.table, state.added)
        metadata = pq.read_schema(original).metadata
        write_dataset(paths.out / "dataset", grown.replace_schema_metadata(metadata))
    else:
        with atomic_dir(paths.out / "dataset") as tmp:
            shutil.copy(original, tmp / FILE)


def _say(done: Round, first: str) -> None:
    r = done.record
    f = r["fidelity"][first]
    opt = r["optimum"]
    console.print(
        f"round {r['round']}: {done.simulated} simulated now; {first} rho {f['spearman']:.3f}, "
        f"median relative error {100 * f['median_relative_error']:.1f} %, optimum "
        f"{opt['predicted'][first]:.4g} predicted vs {opt['simulated'][first]:.4g} simulated; "
        f"{100 * r['clean_fraction']:.0f} % clean; "
        + (
            "target met, stop"
            if done.target_met
            else "nothing new to learn from, stop"
            if done.nothing_new
            else f"{r['added']} added"
        )
        + f"; {done.seconds:.1f} s"
    )


def _track(
    params: Params, paths: Paths, rounds: list[dict[str, Any]], artifacts: tuple[Path, ...]
) -> None:
    """A parent run for the invocation and a child per round, linked to the runs that made
    their models and fronts (train and optimize for the first round, the previous round after)."""
    experiment = tracking.experiment_name(params.robot)
    mlflow = tracking.setup(experiment)

    def find(source: str, tag: str, digest: str) -> str:
        return tracking.latest_run(mlflow, experiment, source, tag, digest) or "unknown"

    train_run = find("train", tracking.MODELS_DIGEST_TAG, models_digest(paths.models))
    optimize_run = find("optimize", tracking.OPTIMUM_DIGEST_TAG, optimum_digest(paths.optimize))
    tags = tracking.tags("refine")
    parent_tags = {
        **tags,
        tracking.SURROGATE_RUN_TAG: train_run,
        tracking.OPTIMIZE_RUN_TAG: optimize_run,
        tracking.MODELS_DIGEST_TAG: models_digest(paths.out / "models"),
        tracking.OPTIMUM_DIGEST_TAG: optimum_digest(paths.out / "optimize"),
    }
    with mlflow.start_run(run_name="refine", tags=parent_tags):
        settings = {"refine": params.refine.model_dump(), "robot": params.robot}
        mlflow.log_params(tracking.flatten({**settings, "surface": params.surface}))
        mlflow.log_metric("rounds", len(rounds))
        for path in artifacts:
            mlflow.log_artifact(str(path), artifact_path="report")
        links = {tracking.SURROGATE_RUN_TAG: train_run, tracking.OPTIMIZE_RUN_TAG: optimize_run}
        for r in rounds:
            rdir = paths.out / f"round-{r['round']}"
            with mlflow.start_run(
                run_name=f"refine-{r['round']}",
                nested=True,
                tags={**tags, **links, "round": str(r["round"])},
            ) as child:
                mlflow.log_metrics(_metrics(r))
                if (rdir / "models").is_dir():
                    mlflow.log_artifacts(str(rdir / "models"), artifact_path="models")
                    mlflow.set_tag(tracking.MODELS_DIGEST_TAG, models_digest(rdir / "models"))
                    mlflow.set_tag(tracking.OPTIMUM_DIGEST_TAG, optimum_digest(rdir / "optimize"))
                    run_id = child.info.run_id
                    links = {tracking.SURROGATE_RUN_TAG: run_id, tracking.OPTIMIZE_RUN_TAG: run_id}


def _metrics(record: dict[str, Any]) -> dict[str, float]:
    """A round's numbers as MLflow metrics (NaN left out: MLflow rejects it)."""
    out = {"added": float(record["added"]), "seconds": float(record["seconds"])}
    for name, values in record["fidelity"].items():
        out.update({f"fidelity.{name}.{k}": float(v) for k, v in values.items()})
    for kind, values in record["optimum"].items():
        out.update({f"optimum.{kind}.{n}": float(v) for n, v in values.items()})
    return {k: v for k, v in out.items() if v == v}
