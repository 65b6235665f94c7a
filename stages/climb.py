"""`ftfof climb`: one trajectory on the whole robot climbing the wall -> Parquet, JSON, PNG."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline import catalog
from stages.common import (
    BaselineOption,
    ParamsOption,
    PointsOption,
    UnitOption,
    console,
    stage,
)

OPTIMIZE = catalog.path("polish_optimize")
OUT_DIR = catalog.path("climbs")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    baseline: Annotated[str | None, BaselineOption] = None,
    points: Annotated[str | None, PointsOption] = None,
    unit: Annotated[str, UnitOption] = "m",
    row: Annotated[int | None, typer.Option(help="A row of the front (--optimize).")] = None,
    optimum: Annotated[bool, typer.Option(help="The chosen optimum (--optimize).")] = False,
    optimize: Annotated[Path, typer.Option(help="The optimum and its front.")] = OPTIMIZE,
    out_dir: Annotated[Path, typer.Option(help="Where the climb's files go.")] = OUT_DIR,
    allow_infeasible: Annotated[
        bool, typer.Option(help="Climb a trajectory the robot's rules refuse; named -infeasible.")
    ] = False,
    controller: Annotated[
        str | None,
        typer.Option(
            help="The stance force control: none, weights, replan or both (climb.controller)."
        ),
    ] = None,
    compare_controllers: Annotated[
        bool, typer.Option(help="Climb once with each controller; writes <name>.controllers.json.")
    ] = False,
) -> None:
    """Climb the wall with the whole robot (climb.steps swings, one leg at a time), the swinging
    foot on the given trajectory; writes its channels, IMU, per-step metrics and traces."""
    from ftfof.climb.outcome import CONTROLLERS, ended, run_climb
    from ftfof.errors import ParamsError
    from ftfof.evaluate.pick import Source
    from ftfof.pipeline.bench import context_of
    from ftfof.pipeline.climb import climb_spec, write_climb
    from ftfof.pipeline.climb import compare_controllers as compare
    from ftfof.pipeline.params_file import load_params
    from ftfof.robot import check_points, parse_points

    if sum((baseline is not None, points is not None, row is not None, optimum)) != 1:
        raise ParamsError("climb", "give exactly one of --baseline, --points, --row, --optimum")
    params = load_params(params_path)
    if controller is not None:
        if controller not in CONTROLLERS:
            raise ParamsError(
                "--controller", f"{controller!r} is not one of {', '.join(CONTROLLERS)}"
            )
        params = params.model_copy(
            update={"climb": params.climb.model_copy(update={"controller": controller})}
        )
    X = None
    if points is not None:
        X = parse_points(points, unit)
        check_points(X, unit, context_of(params), allow_infeasible)
    source = Source(row=row, baseline=baseline, points=X)
    name, spec = climb_spec(params, source, optimize, allow_infeasible)
    title = f"{params.robot} on {params.surface}: {name}"
    if compare_controllers:
        for key, row in compare(spec, out_dir, title, params.acquire.workers).items():
            fell = f"FELL: {row['fall']}" if row["fell"] else "climbed"
            console.print(
                f"  {key:8s} slip {1e3 * row['slip_distance']:7.3f} mm (path"
                f" {1e3 * row['slip_path']:7.3f} mm), peak {1e3 * row['max_slip_velocity']:7.2f}"
                f" mm/s, {fell}"
            )
        return
    out = run_climb(spec)
    paths = write_climb(out, out_dir, title)
    s = out.summary
    console.print(f"{ended(out)} -> {paths['metrics']}")
    figures = ("jitter", "jitter_step", "peak_pull", "slip", "min_bend_radius", "pitch_range")
    for key in (*figures, "torque_ratio"):
        console.print(f"  {key:16s} {s[key]:10.4g}")
    if out.run.error:
        raise typer.Exit(1)
