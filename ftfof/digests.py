"""Content digests: the one way the pipeline names a file, a set of files or settings by what
they hold. Each is SHA-256 hex, cut to ``length`` digits where a short name suffices."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable
from pathlib import Path

from ftfof.errors import DataError


def bytes_sha256(data: bytes, length: int = 64) -> str:
    """SHA-256 hex of ``data``, its first ``length`` digits."""
    return hashlib.sha256(data).hexdigest()[:length]


def file_sha256(path: Path, length: int = 64) -> str:
    """SHA-256 hex of one file's bytes."""
    return bytes_sha256(path.read_bytes(), length)


def json_sha256(data: object, length: int = 64) -> str:
    """SHA-256 of ``data`` as canonical JSON (sorted keys; other objects as their ``str``)."""
    return bytes_sha256(json.dumps(data, sort_keys=True, default=str).encode(), length)


def files_sha256(paths: Iterable[Path], length: int = 16, root: Path | None = None) -> str:
    """SHA-256 over (name, bytes) of several files, in name order; ``length`` hex digits. The
    name is the file's name, or its path relative to ``root`` when given."""

    def name(path: Path) -> str:
        return path.name if root is None else path.relative_to(root).as_posix()

    h = hashlib.sha256()
    for path in sorted(paths, key=name):
        h.update(name(path).encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:length]


def tree_sha256(root: Path, pattern: str, length: int = 16) -> str:
    """:func:`files_sha256` of the files under ``root`` matching ``pattern``, named by their path
    relative to it: the same tree gives the same digest wherever it is checked out."""
    return files_sha256(root.rglob(pattern), length, root)


def models_digest(directory: Path) -> str:
    """Names a set of trained surrogates: every file in the model directory.

    The train run is tagged with it, so a later stage finds the run that produced its models
    without a run id inside the (DVC-tracked) model directory.
    """
    if not directory.is_dir():
        raise DataError(str(directory), "no trained models (run `ftfof train` first)")
    return files_sha256(p for p in directory.iterdir() if p.is_file())
