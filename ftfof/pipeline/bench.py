"""What a run builds from its params, one way for every command: the robot context, the simulated
bench and the baselines on it."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from ftfof.config import Params, Surface
from ftfof.errors import ParamsError
from ftfof.robot import RobotContext, robot_context
from ftfof.seeds import seed_for
from ftfof.sim.spec import Bench, SampleSpec
from ftfof.trajectory.baselines import common_trajectories
from ftfof.trajectory.piecewise import Sampled


def context_of(params: Params) -> RobotContext:
    """The selected robot on the selected surface."""
    return robot_context(
        params.robot,
        params.selected_robot,
        params.selected_surface,
        params.platform.protocol,
        params.feasibility,
        seed_for(params.base.seed, "limits"),
    )


def bench(params: Params, ctx: RobotContext, surface: Surface | None = None) -> Bench:
    """The platform with the selected robot on ``surface`` (default: the selected surface)."""
    return Bench(
        ctx.robot,
        surface or params.selected_surface,
        params.platform,
        params.acquire,
        params.base.seed,
    )


def baseline_trajectories(params: Params, ctx: RobotContext) -> dict[str, Sampled]:
    """The common trajectories every optimum is compared with, from this run's seed."""
    return common_trajectories(
        ctx.policy, params.baselines, seed_for(params.base.seed, "baselines")
    )


def baseline_specs(
    on: Bench, trajectories: Mapping[str, Sampled], names: Iterable[str] | None = None
) -> list[SampleSpec]:
    """One spec per baseline (``names`` in order; default all), keyed ``baseline:<name>``."""
    return [
        on.analytic(f"baseline:{n}", 0, trajectories[n])
        for n in (trajectories if names is None else names)
    ]


def parse_points(text: str, unit: str) -> np.ndarray:
    """The 12 control values P3x..P12x, P3z..P12z as written on a command line, in metres."""
    scale = {"m": 1.0, "mm": 1e-3}.get(unit)
    if scale is None:
        raise ParamsError("--unit", f"must be m or mm (got {unit!r})")
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise ParamsError("--points", "must be 12 comma-separated numbers") from None
    if len(values) != 12:
        raise ParamsError("--points", f"needs 12 values P3x..P12z (got {len(values)})")
    return np.array(values) * scale


def check_points(X: np.ndarray, unit: str, ctx: RobotContext, allow_infeasible: bool) -> list[str]:
    """The rules of ``ctx``'s policy that the control points ``X`` (m) break; refused unless
    ``allow_infeasible``. Values a thousand times off the robot's reach are refused either way,
    with the unit they were most likely meant in."""
    reach = float(np.max(ctx.limits.position))
    size = float(np.max(np.abs(X)))
    if unit == "m" and size > 10 * reach and size * 1e-3 <= 2 * reach:
        raise ParamsError(
            "--points",
            f"reach {size:g} m, {size / reach:.0f} times the robot's {reach:g} m: they look like "
            "millimetres (add --unit mm)",
        )
    if unit == "mm" and 0 < size < reach / 100 and size * 1e3 <= 2 * reach:
        raise ParamsError(
            "--points",
            f"reach {1e3 * size:g} mm, 1/{reach / size:.0f} of the robot's {1e3 * reach:g} mm: "
            "they look like metres (drop --unit mm)",
        )
    failed = ctx.policy.check(X).failed(0)
    if failed and not allow_infeasible:
        raise ParamsError(
            "--points",
            f"{ctx.name} cannot run them: {'; '.join(failed[:3])} "
            "(--allow-infeasible simulates them anyway, marked as such)",
        )
    return failed
