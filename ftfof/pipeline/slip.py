"""`ftfof slip`: the climbing robot under slip, one climb of ``evaluate.slip_scenario`` under
each controller (:data:`ftfof.climb.outcome.CONTROLLERS`); its files, and the table the report
reads."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ftfof.climb.model import ClimbSpec
from ftfof.climb.outcome import CONTROLLERS
from ftfof.climb.specs import scenario_climb, slip_name, slip_table, slip_title
from ftfof.config import Params
from ftfof.pipeline.bench import baseline_trajectories, context_of
from ftfof.pipeline.climb import compare_controllers, spec_for
from ftfof.pipeline.console import console
from ftfof.pipeline.summaries import write_metrics
from ftfof.robot import RobotContext
from ftfof.trajectory.piecewise import Sampled


def run(params: Params, out_dir: Path, record: Path, workers: int | None) -> dict[str, Any]:
    """The slip stage: the comparison where ``evaluate.slip_comparison`` asks for it and the robot
    climbs, its climbs under ``out_dir``; writes ``record``: the scenario and per controller its
    slip figures (``slip`` None where it did not run)."""
    ctx = context_of(params)
    scenario = params.evaluate.slip_scenario
    table = None
    out_dir.mkdir(parents=True, exist_ok=True)
    if params.evaluate.slip_comparison and ctx.robot.climber is not None:
        trajectory = baseline_trajectories(params, ctx)[scenario.trajectory]
        spec, title = slip_scenario_spec(params, ctx, trajectory)
        pool = params.acquire.workers if workers is None else workers
        table = slip_comparison(spec, title, out_dir, pool)
    figure = f"{slip_name(scenario)}.controllers.png"  # compare_controllers draws it
    doc = {"scenario": scenario.model_dump(), "slip": table, "figure": figure}
    write_metrics("slip", record, doc)
    return doc


def slip_scenario_spec(
    params: Params, ctx: RobotContext, trajectory: Sampled
) -> tuple[ClimbSpec, str]:
    """``evaluate.slip_scenario``'s climb of ``trajectory`` and its title; a scenario time
    outside the climb is refused here, before anything runs."""
    scenario = params.evaluate.slip_scenario
    params = params.model_copy(update={"climb": scenario_climb(scenario, params.climb)})
    spec = spec_for(params, ctx, slip_name(scenario), trajectory, None, "evaluate.slip_scenario")
    return spec, slip_title(ctx.name, params.surface, scenario)


def slip_comparison(
    spec: ClimbSpec, title: str, out_dir: Path, workers: int = 0
) -> dict[str, dict[str, Any]]:
    """The slip scenario's climb (:func:`slip_scenario_spec`) under each controller
    (:func:`compare_controllers`, its files in ``out_dir``, ``workers`` as there): per
    controller its slip_distance, slip_path, max_slip_velocity and fell."""
    console.print(f"slip comparison: {title}, under each of {', '.join(CONTROLLERS)}")
    return slip_table(compare_controllers(spec, out_dir, title, workers, "slip comparison"))
