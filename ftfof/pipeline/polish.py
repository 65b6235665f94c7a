"""The `polish` run: NSGA-II on the simulator from the trajectories refine's check passed, RHS on
what the simulator measured, written as an optimize directory (refine's front, the polished
trajectories after it) that `evaluate` reads; tracked in MLflow linked to the refine run.

Each batch the check judges is appended to a journal: the search is deterministic, so a killed
run re-run replays its generations from the journal instead of simulating them again.
"""

from __future__ import annotations

import json
import os
import shutil
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ftfof.config import Params
from ftfof.digests import bytes_sha256, models_digest
from ftfof.evaluate.run import Inputs, decision
from ftfof.files import atomic_dir
from ftfof.optimize.polish import Polished, polish, polish_report, polish_settings, polished_outcome
from ftfof.optimize.search import ConvergenceRecord
from ftfof.optimize.select import SimulatorCheck, Verdict, fine_policy
from ftfof.pipeline import tracking
from ftfof.pipeline.artefacts import (
    FRONT_FILE,
    OPTIMUM_FILE,
    POLISH_READS,
    check_models,
    optimum_digest,
    read_optimum,
    write_optimum,
)
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.console import console, progress
from ftfof.pipeline.jobs import close_resumable, open_resumable
from ftfof.pipeline.registry import registered, used_loss
from ftfof.pipeline.summaries import write_metrics
from ftfof.report import run_metrics
from ftfof.robot import RobotContext
from ftfof.trajectory.bezier import DECISION_NAMES

JOURNAL = "journal.jsonl"
OPTIMUM = "optimize"  # under the run's directory: what evaluate reads
# the check's numbers for polished trajectories (each seeds its perturbed copies): apart from any
# front's rows, so no polished trajectory draws the copies of a front row
FIRST_ROW = 1_000_000
CONFIRM_ROW = 2_000_000  # the same for the fresh copies of the confirmation


@dataclass(frozen=True)
class Paths:
    optimize: Path  # refine's optimum and front
    models: Path  # the surrogates they were found on (the polished rows' predictions)
    out: Path  # the journal, and optimize/ when done
    report: Path  # reports/polish.json


def run(params: Params, paths: Paths, workers: int | None = None) -> dict[str, Any]:
    """Polish refine's verified candidates in simulation; write ``out/optimize`` and the report.

    With ``polish.generations`` 0, or an optimum no simulator check passed (``verify_candidates``
    0), refine's optimum is passed on as it is."""
    started = time.perf_counter()
    if workers is not None:
        params = params.model_copy(
            update={"acquire": params.acquire.model_copy(update={"workers": workers})}
        )
    ctx = context_of(params)
    inputs = read_optimum(paths.optimize, ctx.name, POLISH_READS)
    check_models(inputs, paths.optimize, paths.models)
    identity = {
        "params": params.model_dump(
            exclude={"acquire": {"workers", "scheduler", "batch"}, "evaluate": True, "logs": True}
        ),
        "optimum": inputs.digest,
        "models": models_digest(paths.models),
    }
    key = open_resumable(paths.out, identity)
    passed = [Verdict(**v) for v in inputs.optimum["simulator_check"] if v["ok"]]
    with _tracked(params, inputs) as mlflow:  # open for the search: the run spans it
        if params.polish.generations == 0:
            report: dict[str, Any] = {"polished": False, "reason": "polish.generations is 0"}
        elif not passed:
            report = {"polished": False, "reason": "refine's optimum was not simulator-checked"}
        else:
            report = _polish(params, ctx, inputs, passed, paths)
        if not report["polished"]:
            why = report["reason"]
            console.print(f"[yellow]polish: {why}; refine's optimum is passed on as it is")
            with atomic_dir(paths.out / OPTIMUM) as tmp:
                for name in (FRONT_FILE, OPTIMUM_FILE):
                    shutil.copy(paths.optimize / name, tmp / name)
        report["seconds"] = round(time.perf_counter() - started, 2)
        write_metrics("polish", paths.report, report)
        _log(mlflow, params, report, paths)
    close_resumable(paths.out, key)
    return report


def _polish(
    params: Params, ctx: RobotContext, inputs: Inputs, passed: list[Verdict], paths: Paths
) -> dict[str, Any]:
    """The search in simulation from the ``passed`` candidates (their verdicts taken as
    measured), RHS on the measured result written to ``out/optimize``; the report."""
    cfg, opt = params.polish, params.optimize
    passed = sorted(passed, key=lambda v: v.row != inputs.optimum["front_row"])  # refine's first
    start = np.array([decision(inputs, v.row) for v in passed])
    console.print(
        f"polish {ctx.name}: NSGA-II on the simulator, {cfg.population} trajectories x "
        f"{cfg.generations} generations from {len(start)} verified candidates, on "
        f"{', '.join(ctx.robot.objectives[: cfg.priorities])}"
    )
    searched, result = _searched(params, ctx, start, passed, paths.out / JOURNAL)
    if not searched:
        why = f"none of the {result.simulated} trajectories simulated passed the check"
        return {"polished": False, "reason": why, "simulated": result.simulated}
    if not len(result.X):
        why = "no polished trajectory passed again with fresh copies"
        return {"polished": False, "reason": why, "simulated": result.simulated}
    from ftfof.optimize.problem import TrajectoryProblem
    from ftfof.surrogate.store import load_surrogate

    problem = TrajectoryProblem(
        ctx.policy, load_surrogate(paths.models), ctx.robot.objectives, ctx.rules
    )
    size = len(inputs.front)
    front = inputs.front.loc[np.arange(size), list(DECISION_NAMES)].to_numpy(dtype=float)
    earlier = [Verdict(**v) for v in inputs.optimum["simulator_check"]]
    recheck = fine_policy(ctx, opt.recheck_samples)
    origin = inputs.front.origin.tolist()
    outcome = polished_outcome(problem, recheck, front, origin, earlier, result, opt)
    write_optimum(paths.out / OPTIMUM, outcome, ctx, inputs.optimum["models_digest"], opt)
    start_row = inputs.optimum["front_row"]
    before = next(v for v in earlier if v.ok and v.row == start_row)
    return polish_report(
        cfg, ctx.robot.objectives, size, start_row, before, result, outcome, searched
    )


def _searched(
    params: Params, ctx: RobotContext, start: np.ndarray, passed: list[Verdict], journal: Path
) -> tuple[dict[bytes, Verdict], Polished]:
    """The search from ``start`` and the confirmation of its best, under one progress bar (the
    confirmation its last step): the search's verdicts on its best by decision bytes (none when
    nothing passed), and the confirmed result."""
    from ftfof.pipeline.simcheck import simulator_check_of

    cfg = params.polish
    settings = polish_settings(cfg, params.optimize, params.search_seed)
    check = journaled(simulator_check_of(params, ctx), journal)
    fine = fine_policy(ctx, params.optimize.recheck_samples)
    with progress("polish") as bar:
        task = bar.add_task("polish", total=cfg.generations + 1, info="")

        def record(r: ConvergenceRecord) -> None:
            info = f"generation {r.generation}: {r.feasible} feasible, front {r.front}"
            bar.update(task, completed=r.generation, info=info)

        result = polish(
            fine,
            check,
            start,
            settings,
            cfg.priorities,
            cfg.spread,
            FIRST_ROW,
            passed,
            record,
            risk=cfg.risk_sigmas,
        )
        searched = dict(zip((x.tobytes() for x in result.X), result.verdicts, strict=True))
        if searched:
            bar.update(task, info=f"confirming {len(result.X)} with fresh copies")
            result = _confirmed(params, ctx, result, journal)
        bar.update(task, completed=cfg.generations + 1, info="done")
    return searched, result


def _confirmed(params: Params, ctx: RobotContext, result: Polished, journal: Path) -> Polished:
    """The polished front simulated again, each trajectory with ``polish.confirm_copies`` fresh
    copies (perturbations the search never saw), keeping those that pass, with these runs as
    their verdicts: RHS chooses on them, free of the search's choice among fixed draws."""
    from ftfof.pipeline.simcheck import simulator_check_of

    fresh = params.optimize.model_copy(update={"verify_copies": params.polish.confirm_copies})
    check = journaled(
        simulator_check_of(params.model_copy(update={"optimize": fresh}), ctx), journal
    )
    rows = range(CONFIRM_ROW, CONFIRM_ROW + len(result.X))
    verdicts = check(list(rows), result.X)
    keep = [k for k, v in enumerate(verdicts) if v.ok]
    return replace(result, X=result.X[keep], verdicts=[verdicts[k] for k in keep])


def journaled(check: SimulatorCheck, path: Path) -> SimulatorCheck:
    """``check``, each batch it judges appended to ``path``; a batch asked again (a re-run
    replaying the same generations) is read back instead of simulated. A line cut by a kill is
    dropped."""
    done: dict[str, list[Verdict]] = {}
    if path.exists():
        text = path.read_bytes()
        whole = text[: text.rfind(b"\n") + 1]
        if len(whole) != len(text):
            path.write_bytes(whole)
        for line in whole.decode().splitlines():
            entry = json.loads(line)
            done[entry["batch"]] = [Verdict(**v) for v in entry["verdicts"]]

    def judged(rows: Sequence[int], X: np.ndarray) -> list[Verdict]:
        rows_bytes = np.asarray(rows, dtype=np.int64).tobytes()
        batch = bytes_sha256(rows_bytes + np.ascontiguousarray(X, dtype=float).tobytes(), 32)
        if batch in done:
            return done[batch]
        verdicts = check(rows, X)
        with path.open("a") as journal:
            journal.write(json.dumps({"batch": batch, "verdicts": [v.__dict__ for v in verdicts]}))
            journal.write("\n")
            journal.flush()
            os.fsync(journal.fileno())
        return verdicts

    return judged


@contextmanager
def _tracked(params: Params, inputs: Inputs) -> Iterator[Any]:
    """The `polish` run, open while the stage works, linked to the refine run that wrote its
    start."""
    experiment = tracking.experiment_name(params.robot)
    mlflow = tracking.setup(experiment)
    link, _ = tracking.link_tags(
        mlflow,
        experiment,
        "refine",
        tracking.OPTIMUM_DIGEST_TAG,
        inputs.digest,
        tracking.OPTIMIZE_RUN_TAG,
        "Start",
    )
    with mlflow.start_run(run_name="polish", tags={**tracking.tags("polish"), **link}):
        mlflow.log_params(tracking.run_params(params, polish=params.polish.model_dump()))
        yield mlflow


def _log(mlflow, params: Params, report: dict[str, Any], paths: Paths) -> None:
    """The run's metrics and report; tagged with its optimum's digest (evaluate links to it)
    and the model version whose surrogates it searched on (refine's)."""
    mlflow.log_metrics(run_metrics.polish(report))
    mlflow.log_dict(report, "polish.json")
    mlflow.set_tag(tracking.OPTIMUM_DIGEST_TAG, optimum_digest(paths.out / OPTIMUM))
    version = registered(mlflow, params.robot, used_loss(paths.models), paths.models)
    mlflow.set_tag(tracking.MODEL_TAG, version.uri if version else "unregistered")
