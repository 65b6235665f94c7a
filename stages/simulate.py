"""`ftfof simulate`: one trajectory on the simulated platform -> CSV of channels and a PNG."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.files import atomic_path, save_figure
from ftfof.pipeline import catalog
from stages.common import (
    BaselineOption,
    ParamsOption,
    PointsOption,
    UnitOption,
    console,
    stage,
)

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
    import numpy as np

    from ftfof.data.schema import TRAJECTORIES
    from ftfof.errors import ParamsError
    from ftfof.files import read_table
    from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
    from ftfof.pipeline.params_file import load_params
    from ftfof.report.figures import sample_figure
    from ftfof.robot import check_points, parse_points
    from ftfof.sim.records import CHANNELS
    from ftfof.sim.simulate import simulate
    from ftfof.sim.spec import baseline_specs
    from ftfof.trajectory.baselines import BASELINE_NAMES
    from ftfof.trajectory.bezier import DECISION_NAMES

    chosen = [x is not None for x in (points, row, baseline)]
    if sum(chosen) != 1:
        raise ParamsError("simulate", "give exactly one of --points, --row, --baseline")
    params = load_params(params_path)
    ctx = context_of(params)
    on = bench(params, ctx)
    if baseline is not None:
        if baseline not in BASELINE_NAMES:
            raise ParamsError(
                "--baseline", f"unknown baseline {baseline!r} (have {', '.join(BASELINE_NAMES)})"
            )
        trajectories = baseline_trajectories(params, ctx)
        spec, name = baseline_specs(on, trajectories, [baseline])[0], baseline
    else:
        if points is not None:
            X = parse_points(points, unit)
            name = "points"
        else:
            table = read_table(trajectories, TRAJECTORIES, "trajectory table")
            if not 0 <= row < table.num_rows:
                raise ParamsError("--row", f"{row} is outside 0..{table.num_rows - 1}")
            X = np.array([table.column(n)[row].as_py() for n in DECISION_NAMES])
            name = f"row{row}"
        failed = check_points(X, unit if points is not None else "m", ctx, allow_infeasible)
        if failed:
            name += "-infeasible"
            console.print(f"[yellow]infeasible for {ctx.name}: {'; '.join(failed)}")
        spec = on.bezier("sampled", row or 0, X)
    result = simulate(spec)
    out_dir.mkdir(parents=True, exist_ok=True)
    csv = out_dir / f"{name}.csv"
    with atomic_path(csv) as tmp:
        data = np.column_stack([result.channels[c] for c in CHANNELS])
        np.savetxt(tmp, data, delimiter=",", header=",".join(CHANNELS), comments="", fmt="%.7g")
    png = out_dir / f"{name}.png"
    fig = sample_figure(
        result.channels, f"{ctx.name} on {params.surface}: {name} ({result.status})"
    )
    save_figure(fig, png, dpi=110)
    status = "ok" if result.ok else f"FAILED: {result.error}"
    console.print(f"{name}: {status} in {result.wall_time:.2f} s -> {csv}, {png}")
    for key, value in result.scalars.items():
        console.print(f"  {key:22s} {value:10.4f}")
    if not result.ok:
        raise typer.Exit(1)
