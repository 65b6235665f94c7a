"""The payload margin (issue 53): the largest mass added to the trunk at which a trajectory still
climbs every step, by bisection. No peer reports it; it is what a robot engineer asks first of a
foot trajectory ("how much can it carry?").

The bisection is a small state machine so that a pool can run every trajectory's next climb as
soon as its last one ends: :meth:`Bisection.next` says which mass to climb with next (None:
done), :meth:`Bisection.tell` takes the verdict. It first climbs unloaded (a trajectory that
falls there has no margin), then at the ceiling (one that climbs there has at least it), then
halves the interval between the heaviest mass it climbed with and the lightest it fell with
until that is under the resolution.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import dataclass, field, replace
from typing import Any

from ftfof.climb.model import ClimbSpec
from ftfof.climb.outcome import Climbed, run_climb
from ftfof.sim.pool import fork_pool


@dataclass
class Bisection:
    """One trajectory's search for its payload margin, kg."""

    ceiling: float  # the heaviest added mass tried
    resolution: float  # the interval at which it stops
    climbed: float | None = None  # the heaviest mass it climbed with
    fell: float | None = None  # the lightest mass it fell with
    tries: list[tuple[float, bool]] = field(default_factory=list)

    def next(self) -> float | None:
        """The mass to climb with next, None when the margin is known."""
        if not self.tries:
            return 0.0
        if self.climbed is None:  # fell unloaded
            return None
        if self.fell is None:
            return None if self.climbed >= self.ceiling else self.ceiling
        if self.fell - self.climbed <= self.resolution:
            return None
        return round(0.5 * (self.climbed + self.fell), 9)

    def tell(self, mass: float, climbs: bool) -> None:
        """Whether it climbed every step with ``mass`` added."""
        self.tries.append((mass, climbs))
        if climbs:
            self.climbed = mass if self.climbed is None else max(self.climbed, mass)
        else:
            self.fell = mass if self.fell is None else min(self.fell, mass)

    def report(self) -> dict[str, Any]:
        """The margin (0 where it fell unloaded, the ceiling where it climbed there), the
        interval it lies in and every climb tried."""
        return {
            "payload": self.climbed or 0.0,
            "climbs_unloaded": self.climbed is not None,
            "fell_with": self.fell,  # None: climbed at the ceiling
            "ceiling": self.ceiling,
            "tries": [{"mass": m, "climbed": c} for m, c in self.tries],
        }


def with_payload(spec: ClimbSpec, mass: float) -> ClimbSpec:
    """``spec``'s climb with ``mass`` kg added to the trunk (named ``<name>+<grams>g``)."""
    robot = spec.robot
    assert robot.climber is not None
    climber = robot.climber.model_copy(update={"trunk_mass": robot.climber.trunk_mass + mass})
    loaded = robot.model_copy(update={"climber": climber})
    return replace(spec, name=f"{spec.name}+{1e3 * mass:.0f}g", robot=loaded)


def climbs_every_step(out: Climbed) -> bool:
    """The climb neither fell nor failed and made all its steps."""
    run = out.run
    return not run.fell and not run.error and out.summary["steps_done"] == run.spec.climb.steps


def loaded_climbs(
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
