"""A finished run for a notebook: ``ftfof.open_run(".")`` gives the optimum, its front, Table I
and the surrogates' fidelity as DataFrames, and draws the report's own figures.

    import ftfof
    run = ftfof.open_run(".")          # a clone after `dvc repro`
    run.table                          # Table I: trajectory x figure, as simulated
    run.changes                        # the same in % against run.reference
    run.plot_trajectories()            # FTFOF Fig. 11 as in reports/evaluate.html
"""

from __future__ import annotations

import json
from pathlib import Path

import pyarrow.parquet as pq

from ftfof.errors import DataError
from ftfof.evaluate.runs import split_runs
from ftfof.pipeline import catalog
from ftfof.pipeline.artefacts import FRONT_FILE, OPTIMUM_FILE, run_first
from ftfof.report.run import Run


def open_run(root: str | Path = ".") -> Run:
    """The run `dvc repro` left under ``root`` (a clone): any missing or unreadable file is one
    DataError naming it and the command that writes it."""
    root = Path(root)
    optimize = root / catalog.path("polish_optimize")
    metrics = root / catalog.path("metrics")
    simulations = root / catalog.path("evaluate") / "samples.parquet"
    for path, usual in (
        (optimize / OPTIMUM_FILE, "polish"),
        (metrics, "evaluate"),
        (simulations, "evaluate"),
    ):
        if not path.exists():
            raise DataError(str(path), f"missing ({run_first(path.parent, usual)})")
    try:
        optimum = json.loads((optimize / OPTIMUM_FILE).read_text())
        front = pq.read_table(optimize / FRONT_FILE).to_pandas().set_index("row")
        summary = json.loads(metrics.read_text())
        sims = pq.read_table(simulations).to_pandas()
    except (ValueError, OSError) as err:
        raise DataError(str(root), f"unreadable run ({err})") from None
    at_step, *_ = split_runs(sims)  # the runs at the acquisition's settings
    return Run(optimum, front, summary, at_step[at_step.status == "ok"])
