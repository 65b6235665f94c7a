"""Stop requests (Ctrl-C, or SIGTERM from a scheduler) that a running simulation job honours
between batches.

Raised at once, a KeyboardInterrupt would land inside the simulator's Python callbacks, where
Exudyn reports it as that sample's failure, and the failure would be kept as a result. While a job
simulates, a request is only noted; the job stops after the batch it is writing
(:func:`check`), with every finished batch kept.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager

_requested = threading.Event()
_deferring = 0


def request() -> None:
    """A stop is asked for: at once, unless a job is simulating (then after its batch)."""
    _requested.set()
    if not _deferring:
        raise KeyboardInterrupt


@contextmanager
def deferred() -> Iterator[None]:
    """While inside, stop requests wait for :func:`check`."""
    global _deferring
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1


def check() -> None:
    """Stop here if a stop was asked for."""
    if _requested.is_set():
        raise KeyboardInterrupt


def reset() -> None:
    """Forget an earlier request (a new command starts)."""
    _requested.clear()
