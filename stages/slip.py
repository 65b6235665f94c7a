"""Stage `slip`: the climbing robot under slip (evaluate.slip_scenario) with each stance force
controller -> data/slip_comparison (the climbs) and reports/slip.json (the table)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, WorkersOption, console, stage

OUT = path("slips")
RECORD = path("slip_table")
ERRORS = ("mu_error", "adhesion_error")  # the estimator's, median over the slips


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    out: Annotated[Path, typer.Option(help="Where each controller's climb goes.")] = OUT,
    record: Annotated[Path, typer.Option(help="The comparison's table (JSON).")] = RECORD,
    workers: Annotated[int | None, WorkersOption] = None,
) -> None:
    """Climb the slip scenario under each controller: none, weights, replan, both."""
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.slip import run

    doc = run(load_params(params_path), out, record, workers)
    for controller, row in (doc["slip"] or {}).items():
        fell = "FELL" if row["fell"] else "climbed"
        errors = " / ".join("-" if row[k] is None else f"{100 * row[k]:.0f} %" for k in ERRORS)
        console.print(
            f"  {controller:8s} slip {1e3 * row['slip_distance']:7.3f} mm, "
            f"peak {1e3 * row['max_slip_velocity']:7.2f} mm/s, {fell}; "
            f"estimate error mu / F_adh {errors} over {row['estimated_slips']:g} slips"
        )
    if doc["slip"] is None:
        console.print("no comparison: evaluate.slip_comparison is off or the robot cannot climb")
    console.print(f"-> {record}")
