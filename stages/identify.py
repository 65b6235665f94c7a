"""`ftfof identify`: friction and adhesion of a surface from a slip log -> reports/identify.json,
reports/identify.png; ``--write-params`` sets the surface's preset in params.yaml."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, stage

REPORT, FIGURE = path("identify"), path("identify_figure")


@stage
def command(
    surface: Annotated[str, typer.Option(help="The preset the log is of (surfaces: in params).")],
    log: Annotated[Path | None, typer.Option(help="A slip log (CSV: t, Fx, Fz, load).")] = None,
    simulate: Annotated[
        bool, typer.Option("--simulate", help="Run the slip test on the preset first.")
    ] = False,
    write_params: Annotated[
        bool, typer.Option("--write-params", help="Set the surface's friction and strength.")
    ] = False,
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    report: Annotated[Path, typer.Option(help="The JSON report.")] = REPORT,
    figure: Annotated[Path, typer.Option(help="The convergence plot.")] = FIGURE,
) -> None:
    """Estimate mu and F_adh (least squares and the Kalman-like estimator); a bad log stops
    before anything is written, naming file, row and column."""
    from ftfof.errors import ParamsError
    from ftfof.pipeline import identify as ident
    from ftfof.pipeline.params_file import load_params

    params = load_params(params_path)
    if simulate == (log is not None):
        raise ParamsError("identify", "give --log PATH or --simulate, not both")
    slip = ident.simulate_slip(params, surface) if simulate else ident.read_log(log)
    ls, track = ident.identify(slip)
    out = ident.report(ls, track, ident.truth(params, surface) if simulate else None)
    ident.write_outputs(out, track, report, figure)
    if write_params:
        ident.write_surface(params_path, params, surface, track.final)
    console.print(
        f"{surface}: mu = {track.final.mu:.4f} (least squares {ls.mu:.4f}), "
        f"F_adh = {track.final.adhesion:.3f} N per pad (least squares {ls.adhesion:.3f})"
    )
