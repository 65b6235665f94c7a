"""What every command shares: the params option and the error contract.

The contract: every anticipated failure becomes one line on stderr naming what is wrong and where,
with a non-zero exit. Outputs are written all or nothing by :mod:`ftfof.files`.
"""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from typing import ParamSpec, TypeVar

import typer

from ftfof.errors import FtfofError
from ftfof.pipeline.console import console, progress

__all__ = ["ParamsOption", "console", "progress", "stage"]

P = ParamSpec("P")
R = TypeVar("R")

ParamsOption = typer.Option("--params", "-p", help="Parameter file.", dir_okay=False)


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
