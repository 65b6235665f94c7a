"""How long a whole `dvc repro` takes on a machine, from its stages' sizes and the machine's pace.

Two runs were measured on 2-core machines: the committed params (the README's stage times,
`dvc repro -f` in 26 min 44 s at b1ce044, acquire at 0.286 s per sample) and the tiny profile
(its stages' seconds scaled to that pace). Each stage's time is interpolated linearly in its size
(the loop it runs: samples, epochs, generations, climbing steps) between the two, and the sum is
scaled by this machine's seconds per acquire sample against the committed run's (the stages that
simulate are most of the run, and the others run on the same cores). A rough figure: it cannot
know where early stopping ends training, how many of the polish's offspring break a rule and are
never simulated, or what else the machine will be doing.
"""

from __future__ import annotations

from dataclasses import dataclass

from ftfof.config import Climb, Evaluate, Optimize, Polish, Refine, Sample, Train

REFERENCE_PACE = 286.86 / 1004  # s per acquire sample in the committed params' run
OVERHEAD = 98.0  # s outside the stages (DVC, each stage's start, imports): the 45 s of the
# earlier reference run (2-core, 0.131 s per sample), at this run's pace


@dataclass(frozen=True)
class Stage:
    committed: tuple[float, float]  # (size, seconds) at the committed params
    tiny: tuple[float, float]  # (size, seconds) at the tiny profile, at REFERENCE_PACE

    def seconds(self, size: float) -> float:
        """At REFERENCE_PACE: on the line through the two measured runs, never below 0."""
        (s0, t0), (s1, t1) = self.tiny, self.committed
        return max(t0 + (t1 - t0) * (size - s0) / (s1 - s0), 0.0)


# the committed run's stages as their reports time them; evaluate is the rest of its wall (the
# climbs, the slip comparison, the ε study, evaluate, identify). The tiny profile's seconds were
# measured at 0.182 s per acquire sample, here times 1.57
STAGES = {
    "sample": Stage((1000, 3.9), (40, 3.9)),
    "acquire": Stage((1000, 286.9), (40, 12.6)),
    "dataset": Stage((1000, 0.8), (40, 0.4)),
    "train": Stage((400_000, 54.9), (160, 13.9)),
    "optimize": Stage((400_000, 87.1), (480, 5.2)),
    "refine": Stage((150, 167.4), (8, 36.3)),
    "polish": Stage((504, 484.1), (24, 20.4)),
    "evaluate": Stage((80, 420.9), (10, 110.4)),  # Table I's runs the rest
}
REFERENCE_RUN = OVERHEAD + sum(s.committed[1] for s in STAGES.values())  # s: that run's wall


def stage_sizes(
    sample: Sample,
    train: Train,
    optimize: Optimize,
    refine: Refine,
    polish: Polish,
    evaluate: Evaluate,
    climb: Climb,
) -> dict[str, float]:
    """What each stage's time grows with; the climb and slip stages (in evaluate's): six
    trajectories, and four controllers under slip."""
    climbing = climb.steps * (6 + 4 * evaluate.slip_comparison) if evaluate.climb else 0.0
    return {
        "sample": sample.n,
        "acquire": sample.n,
        "dataset": sample.n,
        "train": sample.n * train.epochs * len(train.losses),
        "optimize": optimize.population * optimize.generations,
        "refine": refine.rounds * refine.points,
        "polish": polish.population * (polish.generations + 1),
        "evaluate": climbing,
    }


def whole_run(sizes: dict[str, float], pace: float) -> float:
    """Seconds of a whole `dvc repro` of stages of ``sizes`` at ``pace`` s per acquire sample."""
    stages = sum(stage.seconds(sizes[name]) for name, stage in STAGES.items())
    return (OVERHEAD + stages) * pace / REFERENCE_PACE


def duration(seconds: float) -> str:
    """``seconds`` as a person reads a wait: seconds under two minutes, else minutes."""
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min"
