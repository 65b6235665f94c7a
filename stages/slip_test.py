"""`ftfof slip-test --surface glass`: the slip test in the simulator -> a slip log (CSV)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path as catalog_path
from stages.common import ParamsOption, console, stage


@stage
def command(
    surface: Annotated[str, typer.Option(help="A preset under surfaces: in params.yaml.")],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    out: Annotated[
        Path | None, typer.Option(help="The log (default data/slip/SURFACE.csv).")
    ] = None,
) -> None:
    """Press the pad, set each normal load, drag it until it slips; write t, Fx, Fz, load."""
    from ftfof.pipeline.identify import slip_bench, write_log
    from ftfof.pipeline.params_file import load_params
    from ftfof.sim.identified import simulated_log

    params = load_params(params_path)
    path = out or catalog_path("slip_logs") / f"{surface}.csv"
    log = simulated_log(slip_bench(params, surface))
    write_log(log, path)
    console.print(f"slip test on {surface}: {log.t.size} samples in {path}")
