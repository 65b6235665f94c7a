"""A climb's outcome: whether the robot may climb a trajectory (:func:`checked_name`), the climb
measured (:func:`run_climb`: its IMU, every step's figures and the feet's slip), and the plain
records its files hold (:func:`channel_columns`, :func:`document`, :func:`controller_row`: no
wall time, so equal climbs write equal files on any machine) and its line on a console
(:func:`ended`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ftfof.climb.control.controllers import COMPOSITIONS
from ftfof.climb.estimates import SlipEpisode, episodes, estimate_summary
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
from ftfof.climb.simulate import ClimbRun, chain_of, climb
from ftfof.config import LEG_NAMES
from ftfof.errors import ParamsError
from ftfof.robot import RobotContext
from ftfof.trajectory.piecewise import Sampled

CONTROLLERS: tuple[str, ...] = tuple(COMPOSITIONS)  # climb.controller's values, by name


@dataclass
class Climbed:
    name: str
    run: ClimbRun
    imu: dict[str, np.ndarray]
    steps: list[StepMetrics]
    summary: dict[str, float | bool]
    slip: SlipTotals
    estimates: list[SlipEpisode]  # each slip's estimate beside its pad's truth


def checked_name(
    ctx: RobotContext,
    name: str,
    trajectory: Sampled,
    X: np.ndarray | None,
    allow_infeasible: bool = False,
) -> str:
    """The climb's name for ``trajectory`` (its decision row ``X``, None for an analytic
    baseline); refused, naming the rule, where the robot cannot run it (``allow_infeasible``:
    climbed all the same, its name marked ``-infeasible``)."""
    robot = ctx.robot
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
    return name + "-infeasible" if failed else name


def run_climb(spec: ClimbSpec) -> Climbed:
    """Climb, read the IMU (``spec.climb``'s), and measure every step."""
    run = climb(spec)
    c = run.channels
    cl = spec.climb
    model = ImuModel(
        cl.imu_rate_hz, cl.imu_acc_noise, cl.imu_acc_bias, cl.imu_gyro_noise, cl.imu_gyro_bias
    )
    imu = imu_channels(c["t"], c["body_acc"][:, :2], c["body"][:, 2], c["body_rate"][:, 2],
                       model, spec.seed)  # fmt: skip
    robot = spec.robot
    reached = c["t"][-1] if c["t"].size else 0.0
    rules = StepRules(
        spec.platform.protocol.switch_height,
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
    slips = episodes(spec, c, run.estimates)
    figures = {**summary(steps, run.fell), **slip.summary(), **estimate_summary(slips)}
    return Climbed(spec.name, run, imu, steps, figures, slip, slips)


def channel_columns(c: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """A climb's channels (at the record rate) as named columns, one per leg, joint and axis."""
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
    return columns


def document(out: Climbed) -> dict[str, Any]:
    """A climb's JSON document: its summary, how it ended, what the controller did, the slip by
    foot, each slip's estimate against its pad's truth and one row per step."""
    run = out.run
    return {
        "trajectory": out.name,
        "summary": {k: plain(v) for k, v in out.summary.items()},
        "fall": run.fall_reason,
        "error": run.error,
        "controller": run.spec.climb.controller,
        "control": run.control,
        "slip_by_foot": out.slip.by_foot(),
        "slip_estimates": [e.row() for e in out.estimates],
        "steps": [{k: plain(v) for k, v in row.items()} for row in as_rows(out.steps)],
    }


def controller_row(out: Climbed) -> dict[str, Any]:
    """One controller's row of a comparison: its slip_distance, slip_path, max_slip_velocity,
    its estimator's median mu_error and adhesion_error over its estimated_slips, fell, fall,
    steps_done and what it did."""
    s = out.summary
    figures = ("slip_distance", "slip_path", "max_slip_velocity")
    return {
        **{k: plain(s[k]) for k in (*figures, "mu_error", "adhesion_error", "estimated_slips")},
        "fell": out.run.fell,
        "fall": out.run.fall_reason,
        "steps_done": plain(s["steps_done"]),
        "control": out.run.control,
    }


def ended(out: Climbed) -> str:
    """How a climb ended, for a console: its name, whether it held, fell or failed, its steps and
    its wall time (a console's, not a record's: it differs on every machine)."""
    run = out.run
    state = (
        "FELL: " + run.fall_reason if run.fell else ("FAILED: " + run.error if run.error else "ok")
    )
    steps = f"{int(out.summary['steps_done'])} of {run.spec.climb.steps} steps"
    return f"{out.name}: {state}; {steps} in {run.wall_time:.1f} s"


def plain(value: object) -> object:
    """JSON's value: numpy scalars as Python's, a non-finite number as null."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
