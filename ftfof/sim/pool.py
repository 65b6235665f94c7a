"""Run many independent acquisitions: a local process pool, or a Dask distributed cluster.

Specs travel to the workers (models cannot be pickled once they hold user functions), each worker
builds and solves its batch with one thread, and results stream back in completion order so the
caller can persist them as they arrive. A worker that dies (a hard crash in native code) takes
down the pool and every batch in flight; those samples are then re-run one at a time, each in a
fresh process, so that only the sample that kills its worker is recorded as failed and the run
goes on with a new pool.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
from collections import deque
from collections.abc import Callable, Generator, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from ftfof.sim.records import FailureReason, SampleResult, Status
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec

Task = Callable[[Sequence[SampleSpec]], list[SampleResult]]

# Workers fork from the parent, which has already imported Exudyn and compiled the kernels
# (docs/simulator.md: forking after Exudyn ran is safe and bitwise identical).
POOL_START = "fork"


def simulate_batch(specs: Sequence[SampleSpec]) -> list[SampleResult]:
    """Worker entry point: one thread, one sample after another."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    return [simulate(spec) for spec in specs]


def _batches(specs: Sequence[SampleSpec], size: int) -> list[list[SampleSpec]]:
    return [list(specs[i : i + size]) for i in range(0, len(specs), size)]


def failed(spec: SampleSpec, error: str, reason: FailureReason) -> SampleResult:
    return SampleResult(
        spec.key, spec.source, spec.sample_id, Status.FAILED, error, 0.0, {}, reason=reason
    )


def run_local(
    specs: Sequence[SampleSpec], workers: int, batch: int = 1, task: Task = simulate_batch
) -> Iterator[list[SampleResult]]:
    """Yield each batch's results as soon as it completes (``workers`` 0 = all cores).

    Every spec comes back exactly once, as its own result or as a failed one.
    """
    workers = workers or os.cpu_count() or 1
    queue = deque(_batches(specs, batch))
    if workers == 1:
        for b in queue:
            yield task(b)
        return
    while queue:
        suspects = yield from _pool_pass(queue, workers, task)
        for spec in suspects:
            yield _alone(spec, task)


def fork_pool(workers: int) -> ProcessPoolExecutor:
    """A pool of ``workers`` processes forked from this one, leaving Ctrl-C to it: the
    acquisition's and the climbs' (:func:`ftfof.pipeline.climb.climb_all`)."""
    return ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context(POOL_START),
        initializer=_leave_interrupts_to_the_parent,
    )


def _leave_interrupts_to_the_parent() -> None:
    """A worker ignores Ctrl-C: the terminal sends it to the whole process group, and a stop
    raised inside a simulation's callback would come back as that sample's failure. The parent
    decides when to stop (after the batch in hand)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _pool_pass(
    queue: deque[list[SampleSpec]], workers: int, task: Task
) -> Generator[list[SampleResult], None, list[SampleSpec]]:
    """Run batches off ``queue`` until it is empty or a worker dies; return the specs in flight
    when it died (their results are lost with the pool, and any of them may be the cause)."""
    suspects: list[SampleSpec] = []
    with fork_pool(workers) as pool:
        pending: dict[Future[list[SampleResult]], list[SampleSpec]] = {}

        def submit(n: int) -> None:
            """Up to ``n`` batches; none once the pool is broken (they stay queued)."""
            for _ in range(min(n, len(queue))):
                try:
                    fut = pool.submit(task, queue[0])
                except BrokenProcessPool:
                    return
                pending[fut] = queue.popleft()

        submit(2 * workers)
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                b = pending.pop(fut)
                try:
                    results = fut.result()
                except BrokenProcessPool:
                    suspects.extend(b)
                    continue
                yield results
                submit(1)
    return suspects


def _alone(spec: SampleSpec, task: Task) -> list[SampleResult]:
    """``spec`` in a process of its own: a crash there can only be its own."""
    with fork_pool(1) as pool:
        try:
            return pool.submit(task, [spec]).result()
        except BrokenProcessPool as err:
            return [failed(spec, f"worker crashed: {err}", FailureReason.WORKER_CRASHED)]


def run_dask(
    specs: Sequence[SampleSpec], address: str, batch: int = 1
) -> Iterator[list[SampleResult]]:
    """The same on a Dask distributed cluster at ``address`` (e.g. tcp://127.0.0.1:8786)."""
    from distributed import Client, as_completed

    with Client(address, timeout="30s") as client:
        batches = _batches(specs, batch)
        futures = client.map(simulate_batch, batches, pure=False)
        specs_of = {f.key: b for f, b in zip(futures, batches, strict=True)}
        for fut in as_completed(futures):
            try:
                yield fut.result()
            except Exception as err:  # a worker lost or a remote exception: record, go on
                error = f"{type(err).__name__}: {err}"
                reason = FailureReason.WORKER_CRASHED
                yield [failed(s, error, reason) for s in specs_of[fut.key]]


def run(
    specs: Sequence[SampleSpec], workers: int = 0, batch: int = 1, scheduler: str | None = None
) -> Iterator[list[SampleResult]]:
    if scheduler:
        return run_dask(specs, scheduler, batch)
    return run_local(specs, workers, batch)


def run_all(specs: Sequence[SampleSpec], workers: int = 0) -> list[SampleResult]:
    """All results in the order of ``specs``."""
    order = {s.key: i for i, s in enumerate(specs)}
    out: list[SampleResult | None] = [None] * len(specs)
    for results in run(specs, workers):
        for r in results:
            out[order[r.key]] = r
    return [r for r in out if r is not None]
