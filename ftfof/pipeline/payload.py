"""`ftfof study payload`: each Table I trajectory's payload margin on the climbing robot
(:mod:`ftfof.study.payload`), every trajectory's next climb started as soon as its last ends."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ftfof.climb.outcome import ended
from ftfof.config import Params
from ftfof.errors import ParamsError
from ftfof.files import save_figure, write_json
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.climb import table_specs
from ftfof.pipeline.console import console
from ftfof.report.payload import payload_figure
from ftfof.study.payload import Bisection, loaded_climbs


def run(params: Params, optimize: Path, out: Path, figure: Path, workers: int) -> dict[str, Any]:
    """The payload margin of each Table I trajectory the robot can run and of the optimum in
    ``optimize``, in a pool of ``workers`` (0: all cores); writes ``out`` and ``figure``."""
    ctx = context_of(params)
    if ctx.robot.climber is None:
        raise ParamsError(f"robots.{ctx.name}", "has no climber block: there is no trunk to load")
    specs, skipped = table_specs(params, ctx, optimize)
    cfg = params.study.payload
    searches = {name: Bisection(cfg.ceiling, cfg.resolution) for name in specs}
    for climbed in loaded_climbs(specs, searches, workers):
        console.print(f"  {ended(climbed)}")
    margins = {name: search.report() for name, search in searches.items()}
    report = {
        "robot": ctx.name,
        "surface": params.surface,
        "steps": params.climb.steps,
        "trunk_mass": ctx.robot.climber.trunk_mass,
        "resolution": cfg.resolution,
        "margins": margins,
        "not_climbed": skipped,
    }
    title = f"{ctx.name} on {params.surface}: payload margin ({params.climb.steps} steps)"
    save_figure(payload_figure(margins, title), figure)
    write_json(out, report)
    return report
