"""The climbs a run asks for, built from its config sections: one trajectory's climb with its
surface change checked before anything runs, the same climb under each controller, and
evaluate's slip scenario (the application reads the params and the trajectories; the specs are
built here, so a climb is the same whichever command asks for it)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from ftfof.climb.model import ClimbSpec
from ftfof.climb.outcome import CONTROLLERS
from ftfof.climb.simulate import gait_of
from ftfof.climb.surface import switch_of
from ftfof.config import Platform, Robot, Surface
from ftfof.config.stages import Climb, SlipScenario, Solver, SurfaceChange
from ftfof.seeds import seed_for
from ftfof.trajectory.piecewise import PiecewiseQuintic

# the slip table's: the slides, the estimator's median errors over its slips (ftfof.climb.estimates)
SLIP_FIGURES = (
    "slip_distance",
    "slip_path",
    "max_slip_velocity",
    "mu_error",
    "adhesion_error",
    "estimated_slips",
    "fell",
)


def climb_spec_of(
    name: str,
    trajectory: PiecewiseQuintic,
    robot: Robot,
    surface: Surface,
    platform: Platform,
    solver: Solver,
    climb: Climb,
    surfaces: Mapping[str, Surface],
    seed: int,
    change_key: str = "climb.surface_change",
) -> ClimbSpec:
    """The climb of ``trajectory`` (its stream of ``seed``, the run's base seed); a
    ``climb.surface_change`` outside the climb is refused here, before anything runs, naming
    ``change_key``, where the change came from."""
    spec = ClimbSpec(
        name=name,
        trajectory=trajectory,
        robot=robot,
        surface=surface,
        platform=platform,
        solver=solver,
        climb=climb,
        seed=seed_for(seed, "climb"),
    )
    switch = switch_of(climb.surface_change, surfaces, gait_of(spec).end, change_key)
    return replace(spec, switch=switch)


def controller_specs(spec: ClimbSpec) -> dict[str, ClimbSpec]:
    """``spec``'s climb under each of CONTROLLERS, named ``<name>.<controller>``."""
    return {
        c: replace(
            spec, name=f"{spec.name}.{c}", climb=spec.climb.model_copy(update={"controller": c})
        )
        for c in CONTROLLERS
    }


def slip_name(scenario: SlipScenario) -> str:
    """The slip comparison's climb name: its files are ``<name>.<controller>.*`` and
    ``<name>.controllers.*``."""
    return f"slip_{scenario.trajectory}"


def scenario_climb(scenario: SlipScenario, climb: Climb) -> Climb:
    """``climb`` with the scenario's surface change."""
    change = SurfaceChange(foot=scenario.foot, time=scenario.time, surface=scenario.surface)
    return climb.model_copy(update={"surface_change": change})


def slip_title(robot: str, surface: str, scenario: SlipScenario) -> str:
    """The slip comparison's title: the robot on its surface, and the scenario's change."""
    return (
        f"{robot} on {surface}: {scenario.trajectory}, {scenario.foot} on"
        f" {scenario.surface} at {scenario.time:g} s"
    )


def slip_table(table: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per controller its slip figures (:data:`SLIP_FIGURES`) of its row of the comparison."""
    return {controller: {k: row[k] for k in SLIP_FIGURES} for controller, row in table.items()}
