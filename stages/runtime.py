"""Process-wide settings for pipeline processes (never applied by the library itself)."""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import platform
from collections.abc import MutableMapping

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


# Numerical code paths pinned for every pipeline process, so that the same commit gives the same
# artefacts on any x86-64 machine, Intel or AMD. Each library below otherwise picks its kernels
# by the host: numba compiles for the host CPU (FMA contraction and vector width follow it);
# NumPy dispatches its ufuncs by the host (its AVX-512 groups X86_V4, AVX512_ICL, AVX512_SPR
# change the last bits of the bond law's arithmetic, and a peel's bond-by-bond snaps carry them
# into different forces); OpenBLAS picks its kernels by the host; torch's ATen kernels (the
# loss, softplus, Adam) by the instruction set (AVX-512 sums in another order than AVX2). AVX2
# with FMA (Haswell, x86-64-v3) is the level every x86-64 machine in use has. MKL is kept off
# the numerical path altogether (the surrogate's layers run on our own kernels): it picks its
# kernels by the CPU's vendor too, and its AVX2 branch trained other GRU weights on an AMD than
# on an Intel machine; COMPATIBLE, its branch documented as the same on both, covers any call
# left in torch.
PINNED_X86_64 = {
    "MKL_CBWR": "COMPATIBLE",
    "ATEN_CPU_CAPABILITY": "avx2",
    "NUMBA_CPU_NAME": "haswell",
    "NUMBA_CPU_FEATURES": "",
    "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR",
    "OPENBLAS_CORETYPE": "Haswell",
}


def pin_numerics(environ: MutableMapping[str, str] = os.environ) -> dict[str, str]:
    """Set :data:`PINNED_X86_64` in ``environ`` (x86-64 only); returns what was set.

    Must run before numpy, torch or numba is imported: each reads these variables once, at load
    time (``stages`` imports nothing else first).
    Other architectures keep their native paths (their numbers may differ from x86-64's).
    """
    if platform.machine().lower() not in {"x86_64", "amd64"}:
        return {}
    environ.update(PINNED_X86_64)
    return dict(PINNED_X86_64)
