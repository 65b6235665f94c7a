"""How long a whole `dvc repro` takes on this machine, estimated from acquire's first samples.

Two runs were measured on 2-core machines: the committed params (the README's stage times,
`dvc repro` in 9 min 25 s, acquire at 0.131 s per sample) and the tiny profile (its stages'
seconds scaled to that pace). Each stage's time is interpolated linearly in its size (the loop
it runs: samples, epochs, generations, climbing steps) between the two, and the sum is scaled by
this machine's seconds per acquire sample against 0.131 (the stages that simulate are most of
the run, and the others run on the same cores). A rough figure: it cannot know where early
stopping ends training, how many of the polish's offspring break a rule and are never
simulated, or what else the machine will be doing.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ftfof.config import Params
from ftfof.pipeline.console import console

REFERENCE_PACE = 132.0 / 1004  # s per acquire sample in the committed params' run
OVERHEAD = 45.0  # s of that run outside the stages: DVC, each stage's start, imports
AFTER_S = 10.0  # s of acquire the estimate waits for (or its end, if sooner)


@dataclass(frozen=True)
class Stage:
    size: Callable[[Params], float]  # what its time grows with
    committed: tuple[float, float]  # (size, seconds) at the committed params
    tiny: tuple[float, float]  # (size, seconds) at the tiny profile, at REFERENCE_PACE

    def seconds(self, params: Params) -> float:
        """At REFERENCE_PACE: on the line through the two measured runs, never below 0."""
        (s0, t0), (s1, t1) = self.tiny, self.committed
        return max(t0 + (t1 - t0) * (self.size(params) - s0) / (s1 - s0), 0.0)


def _climbing_steps(p: Params) -> float:
    """The climb and slip stages: six trajectories, and four controllers under slip."""
    return p.climb.steps * (6 + 4 * p.evaluate.slip_comparison) if p.evaluate.climb else 0.0


# the tiny profile's seconds were measured at 0.182 s per acquire sample, here times 0.722
STAGES = {
    "sample": Stage(lambda p: p.sample.n, (1000, 4), (40, 1.8)),
    "acquire": Stage(lambda p: p.sample.n, (1000, 132), (40, 5.8)),
    "dataset": Stage(lambda p: p.sample.n, (1000, 1), (40, 0.2)),
    "train": Stage(
        lambda p: p.sample.n * p.train.epochs * len(p.train.losses), (400_000, 41), (160, 6.4)
    ),
    "optimize": Stage(
        lambda p: p.optimize.population * p.optimize.generations, (400_000, 44), (480, 2.4)
    ),
    "refine": Stage(lambda p: p.refine.rounds * p.refine.points, (150, 65), (8, 16.7)),
    "polish": Stage(
        lambda p: p.polish.population * (p.polish.generations + 1), (696, 116), (24, 9.4)
    ),
    "evaluate": Stage(_climbing_steps, (80, 117), (10, 50.8)),  # Table I's runs the rest
}


def whole_run(params: Params, pace: float) -> float:
    """Seconds of a whole `dvc repro` of ``params`` at ``pace`` s per acquire sample."""
    stages = sum(stage.seconds(params) for stage in STAGES.values())
    return (OVERHEAD + stages) * pace / REFERENCE_PACE


def duration(seconds: float) -> str:
    """``seconds`` as a person reads a wait: seconds under two minutes, else minutes."""
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min"


class FirstSamples:
    """Acquire's progress hook (finished samples, seconds so far): prints the estimate once,
    after ``AFTER_S`` seconds or when the ``todo`` samples are done, whichever is first. The
    pace counts from the first batch back: the pool's start and the batches still in flight
    would make an early pace look slow."""

    def __init__(self, params: Params, todo: int):
        self.params, self.todo, self.said = params, todo, False
        self.first: tuple[int, float] | None = None

    def __call__(self, finished: int, elapsed: float) -> None:
        if self.said or finished <= 0:
            return
        if self.first is None:
            self.first = (finished, elapsed)
        if elapsed < AFTER_S and finished < self.todo:
            return
        self.said = True
        done, since = self.first
        pace = (elapsed - since) / (finished - done) if finished > done else elapsed / finished
        console.print(
            f"estimate: {pace:.2f} s per sample here ({REFERENCE_PACE:.2f} where `dvc repro` "
            f"took 9 min 25 s): the whole run should take about "
            f"{duration(whole_run(self.params, pace))} on these params (README, How long it "
            "takes)",
            soft_wrap=True,  # one line in a log too
        )
