"""Content digests: the one way the pipeline names a file or a set of files by what they hold."""

from __future__ import annotations

import hashlib
from collections.abc import Iterable
from pathlib import Path


def file_sha256(path: Path) -> str:
    """Full SHA-256 hex of one file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def files_sha256(paths: Iterable[Path], length: int = 16) -> str:
    """SHA-256 over (name, bytes) of several files, in name order; ``length`` hex digits."""
    h = hashlib.sha256()
    for path in sorted(paths, key=lambda p: p.name):
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:length]
