"""What every stage shares: paths, atomic writes, progress bars and the error contract.

The contract: a stage either writes all of its outputs or none (each output is written to a
temporary file beside it and renamed into place), and every anticipated failure becomes one line
on stderr naming what is wrong and where, with a non-zero exit.
"""

from __future__ import annotations

import functools
import json
import os
import sys
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, ParamSpec, TypeVar

import pyarrow as pa
import typer
from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from ftfof.errors import DataError, FtfofError

P = ParamSpec("P")
R = TypeVar("R")

console = Console(stderr=True)

ParamsOption = typer.Option("--params", "-p", help="Parameter file.", dir_okay=False)


def repo_root() -> Path:
    """The DVC project root when run by DVC, else the working directory."""
    return Path(os.environ.get("DVC_ROOT", ".")).resolve()


def stage(fn: Callable[P, R]) -> Callable[P, R]:
    """Turn :class:`FtfofError` into one stderr line and its exit code (typer-friendly)."""

    @functools.wraps(fn)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        try:
            return fn(*args, **kwargs)
        except FtfofError as err:
            print(f"error: {err}", file=sys.stderr)
            raise typer.Exit(code=err.exit_code) from None

    return wrapper


@contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it into place only if the block succeeds."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        if tmp_path.exists():
            os.chmod(tmp_path, 0o666 & ~_umask())
        os.replace(tmp_path, path)
    finally:
        tmp_path.unlink(missing_ok=True)


@contextmanager
def atomic_dir(path: Path) -> Iterator[Path]:
    """Yield a fresh temporary directory beside ``path``; on success it replaces ``path`` whole."""
    import shutil

    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=path.parent, prefix=f".{path.name}."))
    try:
        yield tmp
        os.chmod(tmp, 0o777 & ~_umask())
        if path.exists():
            shutil.rmtree(path)
        tmp.rename(path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_json(path: Path, data: Any) -> None:
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")


def read_table(path: Path, schema: pa.Schema, what: str) -> pa.Table:
    """Read a Parquet file and conform it to ``schema``; any problem is one DataError line."""
    import pyarrow.parquet as pq

    from ftfof.data.schema import conform

    if not path.exists():
        raise DataError(str(path), f"{what} not found (run the stage that writes it first)")
    try:
        table = pq.read_table(path)
    except (pa.ArrowException, OSError) as err:
        raise DataError(str(path), f"unreadable {what} ({str(err).splitlines()[0]})") from None
    return conform(table, schema, str(path))


def write_parquet(path: Path, table: pa.Table) -> None:
    import pyarrow.parquet as pq

    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)


def progress(description: str) -> Progress:
    """A rich progress bar on stderr with rate-friendly columns."""
    return Progress(
        TextColumn(f"[bold]{description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[info]}"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        console=console,
        transient=False,
    )
