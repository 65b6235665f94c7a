"""`ftfof export`: any trajectory for a robot's controller, as CSV, JSON or the YAML of a ROS
JointTrajectory."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline import catalog
from stages.common import ParamsOption, console, stage
from stages.picking import BaselineOption, PointsOption, UnitOption, source_of

OPTIMIZE = catalog.path("polish_optimize")
METRICS = catalog.path("metrics")
OUT_DIR = catalog.path("exports")
SUFFIX = {"csv": "csv", "json": "json", "ros-yaml": "yaml"}


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    row: Annotated[
        int | None, typer.Option(help="A row of the front (--optimize); default: the optimum.")
    ] = None,
    baseline: Annotated[str | None, BaselineOption] = None,
    points: Annotated[str | None, PointsOption] = None,
    unit: Annotated[str, UnitOption] = "m",
    optimize: Annotated[Path, typer.Option(help="The optimum and its front.")] = OPTIMIZE,
    metrics: Annotated[
        Path, typer.Option(help="evaluate's metrics (simulated figures).")
    ] = METRICS,
    rate: Annotated[
        float | None, typer.Option(min=1e-6, help="Samples per second (evaluate.export_rate_hz).")
    ] = None,
    fmt: Annotated[
        str,
        typer.Option("--format", help="csv | json | ros-yaml (trajectory_msgs/JointTrajectory)."),
    ] = "csv",
    out: Annotated[
        Path | None, typer.Option(help=f"File to write (default: {OUT_DIR}/<name>).")
    ] = None,
) -> None:
    """Export the optimum, a front row, a baseline or typed points for the robot's controller:
    foot positions and velocities, joint angles and rates, and where the trajectory came from."""
    from ftfof.errors import ParamsError
    from ftfof.files import atomic_path
    from ftfof.pipeline.bench import context_of
    from ftfof.pipeline.export import export
    from ftfof.pipeline.params_file import load_params
    from ftfof.robot import check_points

    names = "--row, --baseline, --points"
    given = {"row": row, "baseline": baseline, "points": points}
    source = source_of("export", names, unit, required=False, **given)
    if fmt not in SUFFIX:
        raise ParamsError("--format", f"unknown format {fmt!r} (have {', '.join(SUFFIX)})")
    params = load_params(params_path)
    if source.points is not None:
        check_points(source.points, source.unit, context_of(params), allow_infeasible=False)
    hz = params.evaluate.export_rate_hz if rate is None else rate
    exported = export(params, source, hz, fmt, optimize, metrics)
    path = out or OUT_DIR / f"{exported.name}.{SUFFIX[fmt]}"
    with atomic_path(path) as tmp:
        tmp.write_text(exported.text, encoding="utf-8")
    console.print(f"{exported.name}: {exported.rows} samples at {hz:g} Hz ({fmt}) -> {path}")
