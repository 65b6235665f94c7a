"""Stage `acquire`: simulate every sampled trajectory and the baselines -> data/acquisition/.

A resumable job (:mod:`ftfof.pipeline.jobs`): a killed run re-run resumes from its pending parts.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, WorkersOption, console, stage

OUT = path("acquisition")
TRAJECTORIES = path("trajectories")
METRICS = path("acquire_metrics")
TIMING = path("acquire_timing")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    trajectories: Annotated[Path, typer.Option(help="Sampled trajectories.")] = TRAJECTORIES,
    out: Annotated[Path, typer.Option(help="Acquisition dataset directory.")] = OUT,
    metrics: Annotated[Path, typer.Option(help="Summary metrics JSON.")] = METRICS,
    timing: Annotated[Path, typer.Option(help="Per-sample wall times (CSV).")] = TIMING,
    workers: Annotated[int | None, WorkersOption] = None,
    scheduler: Annotated[str | None, typer.Option(help="Override acquire.scheduler.")] = None,
    limit: Annotated[
        int | None, typer.Option(min=1, help="Only the first N sampled rows (at least 1).")
    ] = None,
) -> None:
    """Simulate the force-acquisition platform for every trajectory (resumable)."""
    from ftfof.pipeline.estimate import FirstSamples
    from ftfof.pipeline.jobs import FINAL, Acquisition
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.summaries import write_metrics

    job = Acquisition.prepare(load_params(params_path), trajectories, out, limit)
    cfg = job.params.acquire
    n_workers = cfg.workers if workers is None else workers
    address = cfg.scheduler if scheduler is None else scheduler
    todo = job.remaining()
    console.print(
        f"acquire {job.ctx.name} on {job.params.surface}: {len(job.specs)} samples, "
        f"{len(job.specs) - len(todo)} already done, {len(todo)} to simulate"
        + (f" on {address}" if address else "")
    )
    wall = job.simulate(todo, n_workers, address, "acquire", FirstSamples(job.params, len(todo)))
    summary = job.finish(wall, len(todo), timing)
    write_metrics("acquire", metrics, summary)
    console.print(
        f"{summary['ok']} ok, {summary['failed']} failed "
        f"({summary['seconds_per_sample']:.3f} s/sample) -> {out / FINAL}"
    )
