"""`ftfof identify`: friction and adhesion of a surface from a slip log -> reports/identify.json,
and in reports/identify/ the convergence plot and the surface's preset block; ``--write-params``
sets the preset in params.yaml. Without ``--log`` or ``--simulate`` it does what params.yaml's
``identify`` section says (the pipeline's stage)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, stage

if TYPE_CHECKING:
    from ftfof.config import Params

REPORT, FOLDER, LOGS = path("identify"), path("identify_outputs"), path("slip_logs")


SurfaceOption = typer.Option(
    help="The preset the log is of (default identify.surface, else the surface)."
)
LogOption = typer.Option(help="A slip log (CSV: t, Fx, Fz, load).")
SimulateOption = typer.Option("--simulate", help="Run the slip test on the preset first.")
CalibrationOption = typer.Option(
    help="`ftfof calibrate`'s report of this surface: its pull-off strength, with the "
    "identified shear, sets the preset's shear_capacity_ratio."
)
SpeedsOption = typer.Option(
    help="Two drag speeds, m/s, comma-separated (with --simulate): slip tests at each "
    "recover the rate law's n and v*, F_adh,0 taken as the preset's."
)
IfEnabledOption = typer.Option(
    "--if-enabled", help="Do nothing but say so when identify.enabled is false."
)
WriteOption = typer.Option("--write-params", help="Set the surface's identified values.")


@stage
def command(
    surface: Annotated[str | None, SurfaceOption] = None,
    log: Annotated[Path | None, LogOption] = None,
    simulate: Annotated[bool, SimulateOption] = False,
    calibration: Annotated[Path | None, CalibrationOption] = None,
    speeds: Annotated[str | None, SpeedsOption] = None,
    if_enabled: Annotated[bool, IfEnabledOption] = False,
    write_params: Annotated[bool, WriteOption] = False,
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    report: Annotated[Path, typer.Option(help="The JSON report.")] = REPORT,
    folder: Annotated[Path, typer.Option(help="For the plot and the preset block.")] = FOLDER,
) -> None:
    """Estimate mu and F_adh (least squares and the Kalman-like estimator); a bad log stops
    before anything is written, naming file, row and column."""
    from ftfof.identify import fit
    from ftfof.identify.estimate import Estimate
    from ftfof.pipeline import identify as ident
    from ftfof.pipeline.params_file import load_params
    from ftfof.report.identify import convergence_figure
    from ftfof.sim import identified

    params = load_params(params_path)
    paths = ident.IdentifyPaths(report, folder)
    if if_enabled and not params.identify.enabled:
        ident.write_off(paths)
        console.print("identify: off (identify.enabled is false)")
        return
    log, drag_speeds = _inputs(params, log, simulate, speeds)
    name = surface or params.identify.surface or params.surface
    on = ident.slip_bench(params, name)
    slip = ident.read_log(log) if log is not None else identified.simulated_log(on)
    ls, track = fit.identify(slip)
    true = identified.truth(identified.law_of(on), on.robot) if log is None else None
    source = "simulated slip test" if log is None else str(log)
    out = fit.report(name, source, ls, track, true)
    out["adhesion_0"] = identified.quasi_static_block(on, track.final, log is None)
    if drag_speeds is not None:
        out["rate_law"] = identified.rate_law_block(on, drag_speeds)
    pull_off = ident.read_calibration(calibration, name) if calibration else None
    static = Estimate(track.final.mu, out["adhesion_0"]["estimate"])
    block = identified.preset_of(on, source, static, pull_off)
    ident.write_outputs(out, convergence_figure(out, track), block, paths)
    if write_params:
        ident.write_surface(params_path, name, block, params.surfaces[name])
        console.print(f"wrote the identified values of {name} into {params_path}")
    console.print(
        f"{name}: mu = {track.final.mu:.4f} (least squares {ls.mu:.4f}), "
        f"F_adh = {track.final.adhesion:.3f} N per pad (least squares {ls.adhesion:.3f}), "
        f"F_adh,0 = {static.adhesion:.3f} N; preset block in {paths.preset}"
    )


def _inputs(
    params: Params, log: Path | None, simulate: bool, speeds: str | None
) -> tuple[Path | None, list[float] | None]:
    """The log to read (None: simulate the slip test; identify.log where no option names one)
    and the drag speeds, checked against each other."""
    from ftfof.errors import ParamsError
    from ftfof.identify import fit

    if simulate and log is not None:
        raise ParamsError("identify", "give --log PATH or --simulate, not both")
    drag_speeds = fit.parse_speeds(speeds) if speeds is not None else None
    if drag_speeds is not None and not simulate:
        raise ParamsError("--speeds", "runs simulated slip tests: give it with --simulate")
    if not simulate and log is None and params.identify.log is not None:
        log = Path(params.identify.log)
        if not log.is_relative_to(LOGS):
            raise ParamsError("identify.log", f"{log} is not under {LOGS} (the stage's input)")
    return log, drag_speeds
