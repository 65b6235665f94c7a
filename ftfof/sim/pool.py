"""Run many independent acquisitions: a local process pool, or a Dask distributed cluster.

Specs travel to the workers (models cannot be pickled once they hold user functions), each worker
builds and solves its batch with one thread, and results stream back in completion order so the
caller can persist them as they arrive. A worker that dies (a hard crash in native code) turns
its batch into failed results instead of stopping the run.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from ftfof.sim.simulate import SampleResult, simulate
from ftfof.sim.spec import SampleSpec

# Workers fork from the parent, which has already imported Exudyn and compiled the kernels
# (notes/exudyn.md §5: forking after Exudyn ran is safe and bitwise identical).
POOL_START = "fork"


def simulate_batch(specs: Sequence[SampleSpec]) -> list[SampleResult]:
    """Worker entry point: one thread, one sample after another."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    return [simulate(spec) for spec in specs]


def _batches(specs: Sequence[SampleSpec], size: int) -> list[list[SampleSpec]]:
    return [list(specs[i : i + size]) for i in range(0, len(specs), size)]


def failed(spec: SampleSpec, error: str) -> SampleResult:
    return SampleResult(spec.key, spec.source, spec.sample_id, "failed", error, 0.0, {})


def run_local(
    specs: Sequence[SampleSpec], workers: int, batch: int = 1
) -> Iterator[list[SampleResult]]:
    """Yield each batch's results as soon as it completes (``workers`` 0 = all cores)."""
    workers = workers or os.cpu_count() or 1
    batches = _batches(specs, batch)
    if workers == 1:
        for b in batches:
            yield simulate_batch(b)
        return
    ctx = multiprocessing.get_context(POOL_START)
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
        pending: dict[Future, list[SampleSpec]] = {}
        queue = iter(batches)
        for b in _take(queue, 2 * workers):
            pending[pool.submit(simulate_batch, b)] = b
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                b = pending.pop(fut)
                try:
                    yield fut.result()
                except BrokenProcessPool as err:
                    yield [failed(s, f"worker crashed: {err}") for s in b]
                    return
                for nxt in _take(queue, 1):
                    pending[pool.submit(simulate_batch, nxt)] = nxt


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
                yield [failed(s, f"{type(err).__name__}: {err}") for s in specs_of[fut.key]]


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


def _take(it: Iterator[list[SampleSpec]], n: int) -> Iterable[list[SampleSpec]]:
    for _ in range(n):
        try:
            yield next(it)
        except StopIteration:
            return
