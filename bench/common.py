"""Tiny timing helpers shared by the benchmarks (benchmarks print; they never assert)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any


def best_of(fn: Callable[[], object], repeats: int = 5, number: int = 1) -> float:
    """Best wall time of ``repeats`` runs of ``number`` calls, per call, in seconds."""
    fn()  # warm-up: caches, lazy imports, JIT
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - start) / number)
    return best


def row(label: str, seconds: float, baseline: float | None = None) -> str:
    ratio = f"  {baseline / seconds:8.1f}x vs baseline" if baseline else ""
    return f"{label:<48} {seconds * 1e3:10.3f} ms{ratio}"


def least_cpu(fn: Callable[[], Any], rounds: int) -> tuple[float, list[Any]]:
    """The least CPU seconds of ``rounds`` calls (this core's, so other load on the machine does
    not count), and every call's result in order."""
    seconds, results = [], []
    for _ in range(rounds):
        start = time.process_time()
        results.append(fn())
        seconds.append(time.process_time() - start)
    return min(seconds), results
