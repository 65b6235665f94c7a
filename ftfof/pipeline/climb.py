"""`ftfof climb`: one trajectory on the climbing robot, its channels, metrics and traces."""

from __future__ import annotations

import json
import math
import multiprocessing
import os
import signal
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, get_args

import numpy as np
import pyarrow as pa
from matplotlib.figure import Figure

from ftfof.climb.imu import ImuModel, imu_channels
from ftfof.climb.legs import stroke_breach
from ftfof.climb.metrics import (
    SlipTotals,
    StepMetrics,
    StepRules,
    as_rows,
    slip_totals,
    step_metrics,
    summary,
)
from ftfof.climb.model import ClimbSpec
from ftfof.climb.simulate import ClimbRun, chain_of, climb, gait_of
from ftfof.climb.surface import switch_of
from ftfof.config import LEG_NAMES, Params
from ftfof.config.stages import Controller, SurfaceChange
from ftfof.digests import json_sha256
from ftfof.errors import ParamsError
from ftfof.files import atomic_path, save_figure, write_json, write_parquet
from ftfof.pipeline.bench import bench, context_of
from ftfof.pipeline.export import Source, trajectory_of
from ftfof.pipeline.jobs import MANIFEST, open_resumable, source
from ftfof.report.climb_figure import climb_figure, climb_filmstrip
from ftfof.robot import RobotContext
from ftfof.seeds import seed_for
from ftfof.sim.spec import BASELINE_SEGMENTS
from ftfof.trajectory.piecewise import PiecewiseQuintic, Sampled

CLIMBS = "climb"  # evaluate's climbs, inside its simulations' directory
CONTROLLERS: tuple[str, ...] = get_args(Controller)  # climb.controller's values


@dataclass
class Climbed:
    name: str
    run: ClimbRun
    imu: dict[str, np.ndarray]
    steps: list[StepMetrics]
    summary: dict[str, float | bool]
    slip: SlipTotals


def climb_spec(
    params: Params, source: Source, optimize: Path, allow_infeasible: bool = False
) -> tuple[str, ClimbSpec]:
    """The climb of ``source`` (as `ftfof export` names it) on the selected robot and surface;
    refused, naming the rule, where the robot cannot run it (``allow_infeasible``: climbed all
    the same, its name marked ``-infeasible``)."""
    ctx = context_of(params)
    robot = ctx.robot
    if robot.climber is None:
        raise ParamsError(f"robots.{ctx.name}", "has no climber block: it cannot climb")
    name, trajectory, X, _ = trajectory_of(params, ctx, source, optimize)
    failed = (
        ctx.policy.check(X).failed(0) if X is not None else ctx.policy.path_failures(trajectory)
    )
    stroke = stroke_breach(chain_of(robot), robot.landing.x)
    if stroke:
        raise ParamsError(name, stroke)
    if failed and not allow_infeasible:
        legs = ", ".join(LEG_NAMES)
        raise ParamsError(
            name,
            f"every leg ({legs}) breaks {ctx.name}'s rules: {'; '.join(failed[:3])}"
            " (--allow-infeasible climbs it all the same)",
        )
    if failed:
        name += "-infeasible"
    return name, spec_for(params, ctx, name, trajectory, X)


def spec_for(
    params: Params, ctx: RobotContext, name: str, trajectory: Sampled, X: np.ndarray | None
) -> ClimbSpec:
    """The climb of one trajectory: a Bezier row exactly, an analytic one Hermite-fitted; a
    ``climb.surface_change`` outside the climb is refused here, before anything runs."""
    if X is not None:
        piecewise = bench(params, ctx).bezier("climb", 0, X).trajectory
    else:
        piecewise = PiecewiseQuintic.fit(trajectory, ctx.robot.timing.T3, BASELINE_SEGMENTS)
    spec = ClimbSpec(
        name=name,
        trajectory=piecewise,
        robot=ctx.robot,
        surface=params.selected_surface,
        platform=params.platform,
        solver=params.acquire.solver,
        climb=params.climb,
        seed=seed_for(params.base.seed, "climb"),
    )
    return replace(spec, switch=switch_of(params, gait_of(spec).end))


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
    todo = [n for n in specs if n not in done]
    workers = min(workers or os.cpu_count() or 1, max(len(todo), 1))
    with ProcessPoolExecutor(
        workers, mp_context=multiprocessing.get_context("fork"), initializer=_ignore_interrupts
    ) as pool:
        futures = {pool.submit(run_climb, params, specs[n]): n for n in todo}
        for future in as_completed(futures):
            name = futures[future]
            write_climb(future.result(), out_dir, f"{params.robot} on {params.surface}: {name}")
            done[name] = read_document(out_dir, name)
    write_json(out_dir / MANIFEST, {"fingerprint": key, "complete": True, "source": source()})
    return {n: done[n] for n in specs}


def read_document(out_dir: Path, name: str) -> dict[str, Any]:
    """A written climb's JSON document."""
    return json.loads((out_dir / f"{name}.json").read_text())


def _ignore_interrupts() -> None:
    """Workers leave Ctrl-C to the parent (as the acquisition's pool does)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def run_climb(params: Params, spec: ClimbSpec) -> Climbed:
    """Climb, read the IMU, and measure every step."""
    run = climb(spec)
    c = run.channels
    cl = params.climb
    model = ImuModel(
        cl.imu_rate_hz, cl.imu_acc_noise, cl.imu_acc_bias, cl.imu_gyro_noise, cl.imu_gyro_bias
    )
    imu = imu_channels(c["t"], c["body_acc"][:, :2], c["body"][:, 2], c["body_rate"][:, 2],
                       model, spec.seed)  # fmt: skip
    robot = spec.robot
    reached = c["t"][-1] if c["t"].size else 0.0
    rules = StepRules(
        params.platform.protocol.switch_height,
        robot.foot.swing_clearance,
        robot.timing.T2,
        chain_of(robot).torque_limits,
        robot.foot.film_min_bend_radius,
    )
    steps = [
        step_metrics(c, imu, run.gait, k, rules)
        for k in range(spec.climb.steps)
        if run.gait.lift_off(k) < reached
    ]
    slip = slip_totals(c)
    return Climbed(spec.name, run, imu, steps, {**summary(steps, run.fell), **slip.summary()}, slip)


def write_climb(out: Climbed, out_dir: Path, title: str) -> dict[str, Path]:
    """``<name>.parquet`` (channels at the record rate), ``<name>_imu.parquet``, ``<name>.json``
    (summary and steps), ``<name>.png``; each written whole or not at all."""
    out_dir.mkdir(parents=True, exist_ok=True)
    c = out.run.channels
    columns = {"t": c["t"], "body_plan": c["body_plan"], "swing": c["swing"]}
    for name, parts in (
        ("body", ("x", "z", "pitch")),
        ("body_rate", ("x", "z", "pitch")),
        ("body_acc", ("x", "z", "pitch")),
    ):
        for i, part in enumerate(parts):
            columns[f"{name}_{part}"] = c[name][:, i]
    for leg, L in enumerate(LEG_NAMES):
        columns[f"foot_x_{L}"] = c["foot"][:, 2 * leg]
        columns[f"foot_z_{L}"] = c["foot"][:, 2 * leg + 1]
        columns[f"Fx_{L}"] = c["force"][:, 2 * leg]
        columns[f"Fz_{L}"] = c["force"][:, 2 * leg + 1]
        columns[f"bonds_{L}"] = c["bonds"][:, leg]
        columns[f"curvature_{L}"] = c["curvature"][:, leg]
        columns[f"slip_velocity_{L}"] = c["slip_velocity"][:, leg]
        for j in range(3):
            columns[f"joint_{L}{j + 1}"] = c["joints"][:, 3 * leg + j]
            columns[f"torque_{L}{j + 1}"] = c["torque"][:, 3 * leg + j]
    paths = {
        "channels": out_dir / f"{out.name}.parquet",
        "imu": out_dir / f"{out.name}_imu.parquet",
        "metrics": out_dir / f"{out.name}.json",
        "figure": out_dir / f"{out.name}.png",
        "side": out_dir / f"{out.name}_side.png",
    }
    run = out.run
    document = {
        "trajectory": out.name,
        "summary": {k: _plain(v) for k, v in out.summary.items()},
        "fall": run.fall_reason,
        "error": run.error,
        "wall_time_s": round(run.wall_time, 3),
        "controller": run.spec.climb.controller,
        "control": run.control,
        "slip_by_foot": out.slip.by_foot(),
        "steps": [{k: _plain(v) for k, v in row.items()} for row in as_rows(out.steps)],
    }
    text = json.dumps(document, indent=2) + "\n"  # everything is made before anything is written
    gait = run.gait
    swings = [(gait.lift_off(k), gait.lift_off(k) + gait.swing) for k in range(len(out.steps))]
    figure = climb_figure(c, out.imu, swings, title)
    side = side_view(out, title)
    write_parquet(paths["channels"], pa.table(columns))
    write_parquet(paths["imu"], pa.table(out.imu))
    with atomic_path(paths["metrics"]) as tmp:
        tmp.write_text(text)
    save_figure(figure, paths["figure"], dpi=100)
    save_figure(side, paths["side"], dpi=90)
    return paths


def compare_controllers(
    params: Params, spec: ClimbSpec, out_dir: Path, title: str
) -> dict[str, dict[str, Any]]:
    """``spec``'s climb (its surface change included) under each of CONTROLLERS, one after the
    other, each written as ``<name>.<controller>.*``; returns and writes
    ``<name>.controllers.json``: per controller its slip_distance, slip_path, max_slip_velocity,
    fell and the wall time."""
    table: dict[str, dict[str, Any]] = {}
    for controller in CONTROLLERS:
        climb_ = spec.climb.model_copy(update={"controller": controller})
        name = f"{spec.name}.{controller}"
        out = run_climb(params, replace(spec, name=name, climb=climb_))
        write_climb(out, out_dir, f"{title}, controller {controller}")
        s = out.summary
        table[controller] = {
            "slip_distance": _plain(s["slip_distance"]),
            "slip_path": _plain(s["slip_path"]),
            "max_slip_velocity": _plain(s["max_slip_velocity"]),
            "fell": out.run.fell,
            "fall": out.run.fall_reason,
            "steps_done": _plain(s["steps_done"]),
            "control": out.run.control,
            "wall_time_s": round(out.run.wall_time, 3),
        }
    write_json(out_dir / f"{spec.name}.controllers.json", {"slip": table})
    return table


def slip_comparison(
    params: Params, ctx: RobotContext, trajectory: Sampled, out_dir: Path
) -> dict[str, dict[str, Any]]:
    """``evaluate.slip_scenario``'s climb under each controller (:func:`compare_controllers`,
    its files in ``out_dir``): per controller its slip_distance, slip_path, max_slip_velocity and
    fell."""
    scenario = params.evaluate.slip_scenario
    change = SurfaceChange(foot=scenario.foot, time=scenario.time, surface=scenario.surface)
    climb_ = params.climb.model_copy(update={"surface_change": change})
    params = params.model_copy(update={"climb": climb_})
    name = f"slip_{scenario.trajectory}"
    spec = spec_for(params, ctx, name, trajectory, None)
    title = (
        f"{ctx.name} on {params.surface}: {scenario.trajectory}, {scenario.foot} on"
        f" {scenario.surface} at {scenario.time:g} s"
    )
    table = compare_controllers(params, spec, out_dir, title)
    keys = ("slip_distance", "slip_path", "max_slip_velocity", "fell")
    return {controller: {k: row[k] for k in keys} for controller, row in table.items()}


def side_view(out: Climbed, title: str) -> Figure:
    """The climb from the side: each step's swing a third of the way in, and the last moment."""
    run, spec = out.run, out.run.spec
    chain = chain_of(spec.robot)
    gait = run.gait
    end = float(run.channels["t"][-1]) if run.channels["t"].size else 0.0
    frames = [gait.lift_off(k) + gait.swing / 3 for k in range(len(out.steps))]
    frames = [f for f in frames if f < end] + [end]
    return climb_filmstrip(
        run.channels,
        frames,
        gait.hips,
        float(chain.hip[1]),
        chain.links,
        spec.robot.platform.foot.ankle_height,
        spec.robot.foot.pad_length,
        f"{title}: from the side",
    )


def _plain(value: object) -> object:
    """JSON's value: numpy scalars as Python's, a non-finite number as null."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
