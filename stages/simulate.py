"""`ftfof simulate`: one trajectory on the simulated platform -> CSV of channels and a PNG."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ftfof.files import atomic_path, save_figure
from ftfof.pipeline import catalog
from stages.common import ParamsOption, console, stage
from stages.picking import BaselineOption, PointsOption, UnitOption, source_of

if TYPE_CHECKING:
    from ftfof.sim.records import SampleResult

OUT_DIR = catalog.path("simulate")
TRAJECTORIES = catalog.path("trajectories")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    points: Annotated[str | None, PointsOption] = None,
    unit: Annotated[str, UnitOption] = "m",
    row: Annotated[int | None, typer.Option(help="A row of --trajectories.")] = None,
    trajectories: Annotated[Path, typer.Option(help="Table for --row.")] = TRAJECTORIES,
    baseline: Annotated[str | None, BaselineOption] = None,
    out_dir: Annotated[Path, typer.Option(help="Where the CSV and PNG go.")] = OUT_DIR,
    allow_infeasible: Annotated[
        bool,
        typer.Option(help="Simulate points the robot's rules refuse; outputs named -infeasible."),
    ] = False,
) -> None:
    """Simulate one trajectory (control points, a sampled row, or a baseline) and plot it."""
    from ftfof.pipeline.bench import bench, context_of
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.trajectory import trajectory_of
    from ftfof.robot import check_points
    from ftfof.sim.simulate import simulate
    from ftfof.sim.spec import baseline_specs

    names = "--points, --row, --baseline"
    source = source_of("simulate", names, unit, points=points, sample=row, baseline=baseline)
    params = load_params(params_path)
    ctx = context_of(params)
    on = bench(params, ctx)
    name, trajectory, X, _ = trajectory_of(params, ctx, source, trajectories=trajectories)
    if X is None:  # a common baseline, as the pipeline simulates it
        spec = baseline_specs(on, {name: trajectory})[0]
    else:
        failed = check_points(X, source.unit, ctx, allow_infeasible)
        if failed:
            name += "-infeasible"
            console.print(f"[yellow]infeasible for {ctx.name}: {'; '.join(failed)}")
        spec = on.bezier("sampled", row or 0, X)
    result = simulate(spec)
    csv, png = _write(result, out_dir, name, f"{ctx.name} on {params.surface}: {name}")
    status = "ok" if result.ok else f"FAILED: {result.error}"
    console.print(f"{name}: {status} in {result.wall_time:.2f} s -> {csv}, {png}")
    for key, value in result.scalars.items():
        console.print(f"  {key:22s} {value:10.4f}")
    if not result.ok:
        raise typer.Exit(1)


def _write(result: SampleResult, out_dir: Path, name: str, title: str) -> tuple[Path, Path]:
    """The channels as ``<name>.csv`` and their figure as ``<name>.png`` in ``out_dir``."""
    import numpy as np

    from ftfof.report.figures import sample_figure
    from ftfof.sim.records import CHANNELS

    out_dir.mkdir(parents=True, exist_ok=True)
    csv = out_dir / f"{name}.csv"
    with atomic_path(csv) as tmp:
        data = np.column_stack([result.channels[c] for c in CHANNELS])
        np.savetxt(tmp, data, delimiter=",", header=",".join(CHANNELS), comments="", fmt="%.7g")
    png = out_dir / f"{name}.png"
    save_figure(sample_figure(result.channels, f"{title} ({result.status})"), png, dpi=110)
    return csv, png
