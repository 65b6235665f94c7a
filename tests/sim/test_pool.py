"""A worker that dies takes no other sample with it, and its own sample comes back failed."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

from ftfof.sim.pool import run_local
from ftfof.sim.records import FailureReason, SampleResult, Status

CRASHING = 5


@dataclass(frozen=True)
class Spec:
    """The fields of a sample spec the pool reads."""

    key: str
    source: str
    sample_id: int


def crash_on_one(specs: Sequence[Spec]) -> list[SampleResult]:
    """A stand-in simulation whose process dies hard on sample ``CRASHING``."""
    out = []
    for s in specs:
        if s.sample_id == CRASHING:
            os._exit(3)
        out.append(SampleResult(s.key, s.source, s.sample_id, Status.OK, "", 0.0, {}))
    return out


def test_every_sample_comes_back_once_when_a_worker_dies():
    specs = [Spec(f"sampled:{i}", "sampled", i) for i in range(12)]
    results = [
        r for batch in run_local(specs, workers=2, batch=2, task=crash_on_one) for r in batch
    ]
    assert sorted(r.key for r in results) == sorted(s.key for s in specs)
    by_id = {r.sample_id: r for r in results}
    crashed = by_id.pop(CRASHING)
    assert crashed.status == Status.FAILED and crashed.reason is FailureReason.WORKER_CRASHED
    assert crashed.error.startswith("worker crashed")
    assert all(r.ok for r in by_id.values())
