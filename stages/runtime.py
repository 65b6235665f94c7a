"""Process-wide settings for pipeline processes (never applied by the library itself)."""

from __future__ import annotations

import ctypes
import ctypes.util

_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3


def tune_allocator(mmap_threshold: int = 64 << 20, trim_threshold: int = 256 << 20) -> bool:
    """Keep large temporaries on the heap instead of fresh mmaps.

    The optimiser and the trajectory checks allocate the same few MB of arrays every generation;
    with glibc's defaults each allocation is a fresh mmap whose pages fault in on first touch,
    which measured 2-3x the arithmetic itself (bench/bench_trajectory.py). Returns False where the
    C library has no mallopt (not glibc).
    """
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name)
        mallopt = libc.mallopt
    except (OSError, AttributeError, TypeError):
        return False
    ok = mallopt(_M_MMAP_THRESHOLD, mmap_threshold) == 1
    return ok and mallopt(_M_TRIM_THRESHOLD, trim_threshold) == 1
