"""Yesterday's simulator in today's process: the ``ftfof`` package of a git revision, imported
beside the working tree's, so a benchmark can time both on the same machine and the same load
(interleaved, sample by sample) and compare their channels bit for bit.

The package is extracted with ``git archive`` into a temporary folder and imported with the
working tree's ``ftfof`` modules set aside; its modules then keep their own references, and the
working tree's are put back. Only what the reference imports at import time is its own: the
lumped-leg platform does; the joint-level leg imports lazily and would get today's.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
# the simulator before issue 36 (the bond law's per-case branches)
REFERENCE = "78bd4a4cc915111a14530fa1e6a8ce332cd39940"


def _ours() -> dict[str, Any]:
    return {k: m for k, m in sys.modules.items() if k == "ftfof" or k.startswith("ftfof.")}


def reference_simulate(revision: str = REFERENCE) -> Callable[..., Any]:
    """``ftfof.sim.simulate.simulate`` as it was at ``revision`` (it takes today's specs)."""
    folder = tempfile.mkdtemp(prefix="ftfof-reference-")
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", revision, "ftfof"], check=True, capture_output=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", folder], input=archive, check=True)
    today = _ours()
    for name in today:
        del sys.modules[name]
    sys.path.insert(0, folder)
    try:
        module = importlib.import_module("ftfof.sim.simulate")
    finally:
        sys.path.remove(folder)
        for name in _ours():
            del sys.modules[name]
        sys.modules.update(today)
    return module.simulate
