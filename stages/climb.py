"""`ftfof climb`: one trajectory on the whole robot climbing the wall -> Parquet, JSON, PNG."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ftfof.pipeline import catalog
from stages.common import ParamsOption, console, stage
from stages.picking import BaselineOption, PointsOption, UnitOption, source_of

if TYPE_CHECKING:
    from ftfof.climb.model import ClimbSpec

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
    from ftfof.climb.outcome import ended, run_climb
    from ftfof.pipeline.bench import context_of
    from ftfof.pipeline.climb import climb_spec, with_controller, write_climb
    from ftfof.pipeline.params_file import load_params
    from ftfof.robot import check_points

    names = "--baseline, --points, --row, --optimum"
    given = {"baseline": baseline, "points": points, "row": row, "optimum": optimum}
    source = source_of("climb", names, unit, **given)
    params = with_controller(load_params(params_path), controller)
    if source.points is not None:
        check_points(source.points, source.unit, context_of(params), allow_infeasible)
    name, spec = climb_spec(params, source, optimize, allow_infeasible)
    title = f"{params.robot} on {params.surface}: {name}"
    if compare_controllers:
        _compare(spec, out_dir, title, params.acquire.workers)
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


def _compare(spec: ClimbSpec, out_dir: Path, title: str, workers: int) -> None:
    """The climb under each controller, a line each."""
    from ftfof.pipeline.climb import compare_controllers

    for key, row in compare_controllers(spec, out_dir, title, workers).items():
        fell = f"FELL: {row['fall']}" if row["fell"] else "climbed"
        console.print(
            f"  {key:8s} slip {1e3 * row['slip_distance']:7.3f} mm (path"
            f" {1e3 * row['slip_path']:7.3f} mm), peak {1e3 * row['max_slip_velocity']:7.2f}"
            f" mm/s, {fell}"
        )
