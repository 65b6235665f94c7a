"""`ftfof climb`: Table I's trajectories and the optimum on the climbing robot (the stage), or one
trajectory (the tool); each climb's channels, metrics and traces."""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from concurrent.futures import as_completed
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from ftfof.climb.model import ClimbSpec
from ftfof.climb.outcome import (
    CONTROLLERS,
    Climbed,
    channel_columns,
    checked_name,
    controller_row,
    document,
    ended,
    run_climb,
)
from ftfof.climb.specs import climb_spec_of, controller_specs
from ftfof.config import Params
from ftfof.digests import json_sha256
from ftfof.errors import ParamsError
from ftfof.evaluate.choice import fallback_order, first_that_climbs, rhs_candidates
from ftfof.evaluate.feasible import admitted, climbable
from ftfof.evaluate.pick import Source
from ftfof.evaluate.run import bezier_rows, decision
from ftfof.evaluate.runs import OPTIMUM
from ftfof.evaluate.table import climb_record
from ftfof.files import atomic_path, save_figure, write_json, write_parquet
from ftfof.pipeline.artefacts import read_optimum
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.console import console, progress
from ftfof.pipeline.jobs import MANIFEST, open_resumable, source
from ftfof.pipeline.summaries import write_metrics
from ftfof.pipeline.trajectory import trajectory_of
from ftfof.report.climb_figure import climb_traces, side_view, slip_comparison_figure
from ftfof.robot import RobotContext
from ftfof.sim.pool import fork_pool
from ftfof.sim.spec import BASELINE_SEGMENTS
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.piecewise import PiecewiseQuintic, Sampled

FALLBACKS = "fallbacks"  # under the climbs' folder: the candidates climbed where the optimum fell


def run_table(
    params: Params, optimize: Path, out_dir: Path, record: Path, workers: int | None
) -> dict[str, Any]:
    """The climb stage: Table I's trajectories the robot can run and the chosen optimum in
    ``optimize``, each climbed (:func:`climb_all`, under ``out_dir``); writes ``record``, the
    report's climbing table (:func:`ftfof.evaluate.table.climb_record`): {} where
    ``evaluate.climb`` is off or the robot has no climber."""
    ctx = context_of(params)
    out_dir.mkdir(parents=True, exist_ok=True)
    climbed: dict[str, Any] = {}
    if params.evaluate.climb and ctx.robot.climber is not None:
        specs, skipped = table_specs(params, ctx, optimize)
        console.print(f"climb: the climbing robot climbs {', '.join(specs)}")
        pool = params.acquire.workers if workers is None else workers
        climbs = climb_all(params, specs, out_dir, pool)
        moved = moved_choice(params, ctx, optimize, climbs, out_dir / FALLBACKS)
        climbed = climb_record(climbs, skipped, moved)
    write_metrics("climb", record, climbed)
    return climbed


def moved_choice(
    params: Params,
    ctx: RobotContext,
    optimize: Path,
    climbs: dict[str, dict[str, Any]],
    out_dir: Path,
) -> dict[str, Any] | None:
    """Where the chosen optimum fell on the robot (or its climb failed): the choice moves to the
    next simulator-checked candidate by RHS's order that climbs (:func:`fallback_order`), tried
    one at a time (each written under ``out_dir``, and added to ``climbs``), at most
    ``climb.fallbacks`` of them. Returns the candidate's row (None: none climbed), why the
    choice moved and what was tried; None where the optimum climbed or was not climbed."""
    if OPTIMUM not in climbs or not _fell(climbs[OPTIMUM]):
        return None
    inputs = read_optimum(optimize, ctx.name)
    candidates = rhs_candidates(inputs.optimum, inputs.objectives)
    why = f"the optimum fell on the robot ({_fall(climbs[OPTIMUM])})"

    def fall_of(row: int) -> str | None:
        name, X = _candidate(row), decision(inputs, row)
        spec = spec_for(params, ctx, name, BezierTrajectory(ctx.policy, X), X)
        console.print(f"climb: {why}; the next candidate by RHS's order, row {row}, climbs")
        climbs[name] = climb_all(params, {name: spec}, out_dir / name, 1)[name]
        return _fall(climbs[name]) if _fell(climbs[name]) else None

    order = fallback_order(candidates)[: params.climb.fallbacks]
    row, tried = first_that_climbs(order, fall_of)
    moved = {"row": row, "name": None, "why": why, "tried": tried, "decision": None}
    if row is not None:
        X = decision(inputs, row).tolist()
        moved |= {"name": _candidate(row), "decision": dict(zip(DECISION_NAMES, X, strict=True))}
    return moved


def _candidate(row: int) -> str:
    """A fallback candidate's name in the climbing table."""
    return f"candidate_{row}"


def _fell(document: dict[str, Any]) -> bool:
    """Whether a climb's document ended off the wall or in an error."""
    return bool(document["summary"]["fell"] or document["error"])


def _fall(document: dict[str, Any]) -> str:
    return str(document["fall"] or document["error"])


def table_specs(
    params: Params, ctx: RobotContext, optimize: Path
) -> tuple[dict[str, ClimbSpec], dict[str, str]]:
    """The climbs of Table I's trajectories the robot can run and of the optimum in
    ``optimize``, and the rows it cannot run with the first rules each breaks."""
    inputs = read_optimum(optimize, ctx.name)
    bezier = bezier_rows(ctx, inputs)
    baselines = baseline_trajectories(params, ctx)
    runnable, skipped = climbable(ctx, baselines, bezier, admitted(ctx, baselines, bezier))
    return {n: spec_for(params, ctx, n, t, X) for n, (t, X) in runnable.items()}, skipped


def with_controller(params: Params, controller: str | None) -> Params:
    """``params`` with ``climb.controller`` set to ``controller`` (None: as they are); a name
    that is not one of CONTROLLERS is refused."""
    if controller is None:
        return params
    if controller not in CONTROLLERS:
        raise ParamsError("--controller", f"{controller!r} is not one of {', '.join(CONTROLLERS)}")
    climb = params.climb.model_copy(update={"controller": controller})
    return params.model_copy(update={"climb": climb})


def climb_spec(
    params: Params, source: Source, optimize: Path, allow_infeasible: bool = False
) -> tuple[str, ClimbSpec]:
    """The climb of ``source`` (as `ftfof export` names it) on the selected robot and surface;
    refused, naming the rule, where the robot cannot run it (``allow_infeasible``: climbed all
    the same, its name marked ``-infeasible``)."""
    ctx = context_of(params)
    if ctx.robot.climber is None:
        raise ParamsError(f"robots.{ctx.name}", "has no climber block: it cannot climb")
    name, trajectory, X, _ = trajectory_of(params, ctx, source, optimize)
    name = checked_name(ctx, name, trajectory, X, allow_infeasible)
    return name, spec_for(params, ctx, name, trajectory, X)


def spec_for(
    params: Params,
    ctx: RobotContext,
    name: str,
    trajectory: Sampled,
    X: np.ndarray | None,
    change_key: str = "climb.surface_change",
) -> ClimbSpec:
    """The climb of one trajectory (:func:`ftfof.climb.specs.climb_spec_of`): a Bezier row exactly,
    an analytic one Hermite-fitted."""
    if X is not None:
        piecewise = bench(params, ctx).bezier("climb", 0, X).trajectory
    else:
        piecewise = PiecewiseQuintic.fit(trajectory, ctx.robot.timing.T3, BASELINE_SEGMENTS)
    return climb_spec_of(
        name,
        piecewise,
        ctx.robot,
        params.selected_surface,
        params.platform,
        params.acquire.solver,
        params.climb,
        params.surfaces,
        params.base.seed,
        change_key,
    )


def climb_all(
    params: Params, specs: dict[str, ClimbSpec], out_dir: Path, workers: int
) -> dict[str, dict[str, Any]]:
    """Each spec's climb, written under ``out_dir`` as `ftfof climb` writes one, in a pool of
    ``workers`` (0: all cores); returns each one's document (summary, fall, steps). Resumable:
    a climb already written under the same fingerprint and code is read back, not run again."""
    identity = {
        "robot": params.selected_robot.model_dump(),
        "surface": params.selected_surface.model_dump(),
        "platform": params.platform.model_dump(),
        "solver": params.acquire.solver.model_dump(),
        "climb": params.climb.model_dump(),
        "seed": params.base.seed,
        "trajectories": {n: json_sha256(s.trajectory.coeffs.tolist()) for n, s in specs.items()},
    }
    key = open_resumable(out_dir, identity)
    done = {n: read_document(out_dir, n) for n in specs if (out_dir / f"{n}.json").exists()}
    todo = {n: specs[n] for n in specs if n not in done}
    for name, out in _climbed(todo, workers, "climbs", len(done)):
        write_climb(out, out_dir, f"{params.robot} on {params.surface}: {name}")
        done[name] = read_document(out_dir, name)
    write_json(out_dir / MANIFEST, {"fingerprint": key, "complete": True, "source": source()})
    return {n: done[n] for n in specs}


def _climbed(
    specs: dict[str, ClimbSpec], workers: int, label: str, done: int = 0
) -> Iterator[tuple[str, Climbed]]:
    """Each spec's climb as it finishes, in a pool of ``workers`` (0: all cores), under a progress
    bar ``label`` (``done`` climbs of it finished before) and a line saying how each ended."""
    workers = min(workers or os.cpu_count() or 1, max(len(specs), 1))
    with (
        progress(label) as bar,
        fork_pool(workers) as pool,
    ):
        total = done + len(specs)
        task = bar.add_task(label, total=total, completed=done, resumed=done, info="")
        futures = {pool.submit(run_climb, spec): name for name, spec in specs.items()}
        for future in as_completed(futures):
            out = future.result()
            bar.console.print(f"  {ended(out)}")
            bar.update(task, advance=1, info=out.name)
            yield futures[future], out


def read_document(out_dir: Path, name: str) -> dict[str, Any]:
    """A written climb's JSON document."""
    return json.loads((out_dir / f"{name}.json").read_text())


def write_climb(out: Climbed, out_dir: Path, title: str) -> dict[str, Path]:
    """``<name>.parquet`` (channels at the record rate), ``<name>_imu.parquet``, ``<name>.json``
    (summary and steps), ``<name>.png``; each written whole or not at all."""
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = {
        "channels": out_dir / f"{out.name}.parquet",
        "imu": out_dir / f"{out.name}_imu.parquet",
        "metrics": out_dir / f"{out.name}.json",
        "figure": out_dir / f"{out.name}.png",
        "side": out_dir / f"{out.name}_side.png",
    }
    columns = channel_columns(out.run.channels)
    # everything is made before anything is written
    text = json.dumps(document(out), indent=2) + "\n"
    figure = climb_traces(out, title)
    side = side_view(out, title)
    write_parquet(paths["channels"], pa.table(columns))
    write_parquet(paths["imu"], pa.table(out.imu))
    with atomic_path(paths["metrics"]) as tmp:
        tmp.write_text(text)
    save_figure(figure, paths["figure"], dpi=100)
    save_figure(side, paths["side"], dpi=90)
    return paths


def compare_controllers(
    spec: ClimbSpec, out_dir: Path, title: str, workers: int = 0, label: str = "controllers"
) -> dict[str, dict[str, Any]]:
    """``spec``'s climb (its surface change included) under each of CONTROLLERS, in a pool of
    ``workers`` (0: all cores) under a progress bar ``label``, each written as
    ``<name>.<controller>.*``; returns and writes ``<name>.controllers.json``: per controller its
    slip_distance, slip_path, max_slip_velocity, fell, fall, steps and what it did;
    ``<name>.controllers.png``: the changed foot's slip under each (the foot that slipped most
    under ``none`` without a surface change)."""
    specs = controller_specs(spec)
    outs: dict[str, Climbed] = {}
    for controller, out in _climbed(specs, workers, label):
        write_climb(out, out_dir, f"{title}, controller {controller}")
        outs[controller] = out
    outs = {c: outs[c] for c in CONTROLLERS}
    table = {c: controller_row(out) for c, out in outs.items()}
    leg = spec.switch.leg if spec.switch else int(np.argmax(outs[CONTROLLERS[0]].slip.distance))
    figure = slip_comparison_figure(outs, leg, title)
    save_figure(figure, out_dir / f"{spec.name}.controllers.png", dpi=90)
    write_json(out_dir / f"{spec.name}.controllers.json", {"slip": table})
    return table
