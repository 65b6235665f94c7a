"""A trajectory as a controller reads it: time-sampled foot position, velocity and joint angles,
checked against the robot's rules and the leg's joint and speed limits, with the metadata a lab
notebook needs, and rendered as CSV (a commented metadata header), JSON or the YAML shape of ROS
``trajectory_msgs/JointTrajectory``."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.config.stages import EXPORT_MAX_RATE_HZ
from ftfof.errors import ParamsError
from ftfof.kinematics.legs import Leg, build_leg, joint_rates, within_limits
from ftfof.robot import RobotContext
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.piecewise import Sampled
from ftfof.version import __version__

Array = NDArray[np.float64]

COLUMNS = (
    "t [s]",
    "x [m]",
    "z [m]",
    "vx [m/s]",
    "vz [m/s]",
    "q1 [rad]",
    "q2 [rad]",
    "q3 [rad]",
    "dq1 [rad/s]",
    "dq2 [rad/s]",
    "dq3 [rad/s]",
)


FRAME = (
    "trajectory frame: origin at the foot's start point P0, x along the wall in the step's "
    "direction, z away from the wall"
)
UNITS = {"t": "s", "x, z": "m", "vx, vz": "m/s", "q": "rad", "dq": "rad/s"}


EXPORT_MAX_SAMPLES = 1_000_000  # rows of one exported trajectory (a long T3 at a high rate)


class ExportRateError(ValueError):
    """The export rate gives too few samples, or more than a controller needs (the rate's fault,
    not the leg's)."""


def sample_count(T3: float, rate_hz: float) -> int:
    """The samples over [0, T3] at ``rate_hz``: at least 3, and within EXPORT_MAX_RATE_HZ and
    EXPORT_MAX_SAMPLES (checked before anything is sampled: a rate of 1e9 would build a
    billion-row table); ExportRateError otherwise."""
    if not 0 < rate_hz <= EXPORT_MAX_RATE_HZ:
        raise ExportRateError(
            f"export rate {rate_hz:g} Hz is beyond the bound of {EXPORT_MAX_RATE_HZ:g} Hz "
            "(a controller's loop runs at 1-10 kHz)"
        )
    n = int(np.floor(T3 * rate_hz + 1e-9)) + 1
    if n > EXPORT_MAX_SAMPLES:
        raise ExportRateError(
            f"export rate {rate_hz:g} Hz gives {n} samples over T3 = {T3:g} s, beyond the bound "
            f"of {EXPORT_MAX_SAMPLES} samples"
        )
    if n < 3:
        raise ExportRateError(
            f"export rate {rate_hz:g} Hz gives fewer than 3 samples over T3 = {T3:g} s"
        )
    return n


@dataclass(frozen=True)
class ControllerTrajectory:
    table: Array  # (n, len(COLUMNS))
    within_joint_limits: bool
    peak_joint_speed: Array  # (3,) rad/s

    @property
    def columns(self) -> tuple[str, ...]:
        return COLUMNS


def controller_trajectory(
    trajectory: Sampled, T3: float, leg: Leg, rate_hz: float
) -> ControllerTrajectory:
    """Sample ``trajectory`` over [0, T3] at ``rate_hz`` and solve the leg's IK.

    Joint rates solve J(q) dq = v exactly through the leg's sagittal parameterisation (two free
    joints, the third following from them). Raises ExportRateError for a rate beyond
    :func:`sample_count`'s bounds, ValueError at the first instant the leg cannot reach.
    """
    t = np.linspace(0.0, T3, sample_count(T3, rate_hz))
    s = trajectory.sample(t)
    position, velocity = s.position[0], s.velocity[0]
    theta = leg.inverse(position)
    bad = np.flatnonzero(~np.all(np.isfinite(theta), axis=1))
    if bad.size:
        i = int(bad[0])
        x, z = 1e3 * position[i]
        raise ValueError(
            f"the leg cannot reach the foot point ({x:.2f}, {z:.2f}) mm at t = {t[i]:.4f} s"
        )
    rates = joint_rates(leg, theta, velocity)
    table = np.column_stack([t, position, velocity, theta, rates])
    inside = bool(np.all(within_limits(theta, leg.joint_limits)))
    return ControllerTrajectory(table, inside, np.abs(rates).max(axis=0))


def limit_breaches(out: ControllerTrajectory, leg: Leg) -> list[str]:
    """The leg's limits ``out`` breaks, each with its joint and first instant: a robot cannot run
    a trajectory that leaves a joint's range or outruns its speed."""
    t, theta, rates = out.table[:, 0], out.table[:, 5:8], out.table[:, 8:11]
    breaches = []
    for j in range(3):
        lo, hi = leg.joint_limits[j]
        outside = np.flatnonzero((theta[:, j] < lo - 1e-9) | (theta[:, j] > hi + 1e-9))
        if outside.size:
            i = int(outside[0])
            breaches.append(
                f"q{j + 1} = {theta[i, j]:.4f} rad at t = {t[i]:.4f} s, outside "
                f"[{lo:g}, {hi:g}] rad"
            )
        fast = np.flatnonzero(np.abs(rates[:, j]) > leg.speed_limits[j] * (1 + 1e-9))
        if fast.size:
            i = int(fast[0])
            breaches.append(
                f"dq{j + 1} = {rates[i, j]:.3f} rad/s at t = {t[i]:.4f} s, beyond the "
                f"{leg.speed_limits[j]:g} rad/s limit"
            )
    return breaches


def runnable(
    ctx: RobotContext, name: str, trajectory: Sampled, X: Array | None, rate_hz: float
) -> ControllerTrajectory:
    """``trajectory`` (decision row ``X``, None for an analytic baseline) sampled at ``rate_hz``
    through ``ctx``'s leg; refused where the robot cannot run it (its constraint policy at that
    rate, a joint's range or speed), one ParamsError naming the rule; a rate beyond
    :func:`sample_count`'s bounds first, naming ``--rate``."""
    try:
        sample_count(ctx.policy.timing.T3, rate_hz)  # before a grid at that rate is built
    except ExportRateError as err:
        raise ParamsError("--rate", str(err)) from None
    leg = build_leg(ctx.robot.leg)
    if X is not None:
        failed = ctx.policy.at_rate(rate_hz).check(X).failed(0)
        if failed:
            raise ParamsError(name, f"{ctx.name} cannot run it: {'; '.join(failed[:3])}")
    try:
        out = controller_trajectory(trajectory, ctx.policy.timing.T3, leg, rate_hz)
    except ValueError as err:
        raise ParamsError(name, str(err)) from None
    breaches = limit_breaches(out, leg)
    if breaches:
        raise ParamsError(name, f"{ctx.name}'s leg cannot run it: {'; '.join(breaches[:3])}")
    return out


def export_metadata(
    ctx: RobotContext,
    surface: str,
    name: str,
    rate_hz: float,
    params_hash: str,
    source: dict[str, object],
    simulated: dict[str, float] | str,
    X: Array | None,
) -> dict[str, object]:
    """What a lab notebook needs beside an exported trajectory: the code, robot, surface, frame
    and units, where it came from (``source``), the simulator's figures of it, and its control
    points in mm where it is a Bezier row."""
    metadata: dict[str, object] = {
        "ftfof": __version__,
        "robot": ctx.name,
        "leg": ctx.robot.leg.type,
        "surface": surface,
        "trajectory": name,
        "frame": FRAME,
        "frame_id": f"{ctx.name}_foot_start",
        "units": UNITS,
        "rate_hz": rate_hz,
        "duration_s": ctx.policy.timing.T3,
        "params_hash": params_hash,
        **source,
        "simulated": simulated,
    }
    if X is not None:
        metadata["control_points_mm"] = {
            n: round(1e3 * float(v), 6) for n, v in zip(DECISION_NAMES, X, strict=True)
        }
    return metadata


def simulated_figures(summary: dict, name: str, row: int | None) -> dict[str, float] | str:
    """The simulator's Table I figures for trajectory ``name`` (front row ``row``) from
    evaluate's ``summary``, where evaluate simulated it."""
    table = summary.get("table", {})
    key = "optimum" if row is not None and row == summary.get("optimum_front_row") else name
    if key in table:
        return {k: v for k, v in table[key].items() if not k.endswith("_change")}
    members = summary.get("front_simulated", {}).get("members", [])
    for member in members:
        if row is not None and member.get("row") == row:
            figures = ("peak_pull", "jitter", "min_bend_radius", "max_clearance")
            return {k: member[k] for k in figures if k in member}
    return "not simulated by evaluate"


JOINTS = ("q1", "q2", "q3")
FORMATS = ("csv", "json", "ros-yaml")


def render(out: ControllerTrajectory, metadata: dict[str, object], fmt: str) -> str:
    """``out`` as text in ``fmt``, ``metadata`` (robot, frame, units, digests, figures) with it."""
    if fmt == "csv":
        return _csv(out, metadata)
    if fmt == "json":
        return _json(out, metadata)
    if fmt == "ros-yaml":
        return _ros_yaml(out, metadata)
    raise ValueError(f"unknown format {fmt!r} (have {', '.join(FORMATS)})")


def _flat(metadata: dict[str, object], prefix: str = "") -> list[tuple[str, object]]:
    out: list[tuple[str, object]] = []
    for key, value in metadata.items():
        if isinstance(value, dict):
            out += _flat(value, f"{prefix}{key}.")
        else:
            out.append((f"{prefix}{key}", value))
    return out


def _csv(out: ControllerTrajectory, metadata: dict[str, object]) -> str:
    import io

    lines = [f"# {key}: {value}" for key, value in _flat(metadata)]
    buffer = io.StringIO()
    np.savetxt(buffer, out.table, delimiter=",", header=",".join(COLUMNS), comments="", fmt="%.9g")
    return "\n".join(lines) + "\n" + buffer.getvalue()


def _json(out: ControllerTrajectory, metadata: dict[str, object]) -> str:
    import json

    columns = {name: [float(v) for v in out.table[:, k]] for k, name in enumerate(COLUMNS)}
    return json.dumps({"metadata": metadata, "columns": columns}, indent=1) + "\n"


def _ros_yaml(out: ControllerTrajectory, metadata: dict[str, object]) -> str:
    """trajectory_msgs/JointTrajectory as YAML (no ROS needed to write it): joint names, and per
    point positions, velocities and time_from_start {sec, nanosec}."""
    import yaml

    points = []
    for row in out.table:
        sec, nanosec = divmod(round(float(row[0]) * 1e9), 1_000_000_000)
        points.append(
            {
                "positions": [float(v) for v in row[5:8]],
                "velocities": [float(v) for v in row[8:11]],
                "time_from_start": {"sec": int(sec), "nanosec": int(nanosec)},
            }
        )
    message = {
        "header": {
            "frame_id": str(metadata.get("frame_id", "")),
            "stamp": {"sec": 0, "nanosec": 0},
        },
        "joint_names": list(JOINTS),
        "points": points,
    }
    comment = "".join(f"# {key}: {value}\n" for key, value in _flat(metadata))
    return comment + yaml.safe_dump(message, sort_keys=False, default_flow_style=None)
