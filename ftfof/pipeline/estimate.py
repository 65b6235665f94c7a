"""How long a whole `dvc repro` takes on this machine, estimated from acquire's first samples and
printed (the estimate is :mod:`ftfof.study.duration`)."""

from __future__ import annotations

from ftfof.config import Params
from ftfof.pipeline.console import console
from ftfof.study.duration import REFERENCE_PACE, REFERENCE_RUN, duration, stage_sizes, whole_run

AFTER_S = 10.0  # s of acquire the estimate waits for (or its end, if sooner)


def sizes_of(params: Params) -> dict[str, float]:
    """The sizes of ``params``' stages (:func:`ftfof.study.duration.stage_sizes`)."""
    p = params
    return stage_sizes(p.sample, p.train, p.optimize, p.refine, p.polish, p.evaluate, p.climb)


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
        whole = duration(whole_run(sizes_of(self.params), pace))
        console.print(
            f"estimate: {pace:.2f} s per sample here ({REFERENCE_PACE:.2f} where `dvc repro` "
            f"took {duration(REFERENCE_RUN)}): the whole run should take about "
            f"{whole} on these params (README, How long it takes)",
            soft_wrap=True,  # one line in a log too
        )
