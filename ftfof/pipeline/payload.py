"""`ftfof study payload`: each Table I trajectory's payload margin on the climbing robot
(:mod:`ftfof.study.payload`), every trajectory's next climb started as soon as its last ends."""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from concurrent.futures import FIRST_COMPLETED, Future, wait
from pathlib import Path
from typing import Any

from ftfof.climb.model import ClimbSpec
from ftfof.climb.outcome import Climbed, ended, run_climb
from ftfof.config import Params
from ftfof.errors import ParamsError
from ftfof.files import save_figure, write_json
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.climb import table_specs
from ftfof.pipeline.console import console
from ftfof.report.payload import payload_figure
from ftfof.sim.pool import fork_pool
from ftfof.study.payload import Bisection, climbs_every_step, with_payload


def run(params: Params, optimize: Path, out: Path, figure: Path, workers: int) -> dict[str, Any]:
    """The payload margin of each Table I trajectory the robot can run and of the optimum in
    ``optimize``, in a pool of ``workers`` (0: all cores); writes ``out`` and ``figure``."""
    ctx = context_of(params)
    if ctx.robot.climber is None:
        raise ParamsError(f"robots.{ctx.name}", "has no climber block: there is no trunk to load")
    specs, skipped = table_specs(params, ctx, optimize)
    cfg = params.study.payload
    searches = {name: Bisection(cfg.ceiling, cfg.resolution) for name in specs}
    for climbed in _loaded_climbs(specs, searches, workers):
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


def _loaded_climbs(
    specs: Mapping[str, ClimbSpec], searches: Mapping[str, Bisection], workers: int
) -> Iterator[Climbed]:
    """Each climb as it ends, its verdict told to its trajectory's search, which then names its
    next mass (the order the climbs end in changes no search: each one's climbs run in turn)."""
    with fork_pool(workers or os.cpu_count() or 1) as pool:
        running: dict[Future[Climbed], tuple[str, float]] = {}

        def submit(name: str) -> None:
            mass = searches[name].next()
            if mass is not None:
                running[pool.submit(run_climb, with_payload(specs[name], mass))] = (name, mass)

        for name in specs:
            submit(name)
        while running:
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in done:
                name, mass = running.pop(future)
                climbed = future.result()
                searches[name].tell(mass, climbs_every_step(climbed))
                yield climbed
                submit(name)
