"""What every command shares: the params option and the error contract.

The contract: every anticipated failure becomes one line on stderr naming what is wrong and where,
with a non-zero exit. Outputs are written all or nothing by :mod:`ftfof.files`.
"""

from __future__ import annotations

import functools
import signal
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import ParamSpec, TypeVar

import typer

from ftfof.errors import FtfofError
from ftfof.pipeline import catalog, interrupt
from ftfof.pipeline.console import console, progress

__all__ = [
    "ParamsOption",
    "WorkersOption",
    "console",
    "progress",
    "stage",
]

P = ParamSpec("P")
R = TypeVar("R")

ParamsOption = typer.Option("--params", "-p", help="Parameter file.", dir_okay=False)
# parallel simulations (acquire, refine, polish, evaluate): refused below 0 before anything runs
WorkersOption = typer.Option(
    min=1, help="Override acquire.workers with a worker count (acquire.workers 0: all cores)."
)

# what an interrupted command keeps, and where under its --out (by default its catalog path):
# the resumable ones go on from it when run again
KEPT = {
    "acquire": ("its finished simulations are kept", "acquisition", "pending"),
    "evaluate": ("its finished simulations are kept", "evaluate", "pending"),
    "refine": ("its finished rounds and simulations are kept", "refine", ""),
    "polish": ("its simulated batches are kept", "polish", "journal.jsonl"),
}
INTERRUPTED = 130  # the shell's code for a command stopped by SIGINT


def interrupted(command: str, out: Path | None = None) -> str:
    """The line an interrupted ``command`` (writing to ``out``) leaves: what was kept, and how to
    go on."""
    if command in KEPT:
        what, artefact, inside = KEPT[command]
        where = (out or catalog.path(artefact)) / inside
        return f"interrupted: {what} ({where}); run `ftfof {command}` again to resume"
    return (
        "interrupted: nothing was written (outputs appear whole or not at all); "
        f"run `ftfof {command}` again"
    )


def _stop(signum, frame) -> None:
    interrupt.request()


def stage(fn: Callable[P, R]) -> Callable[P, R]:
    """Turn :class:`FtfofError` into one stderr line and its exit code (typer-friendly)."""

    command = fn.__module__.rpartition(".")[2].replace("_", "-")

    @functools.wraps(fn)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        main = threading.current_thread() is threading.main_thread()
        interrupt.reset()
        handled = (signal.SIGTERM, signal.SIGINT) if main else ()
        previous = {s: signal.signal(s, _stop) for s in handled}
        try:
            return fn(*args, **kwargs)
        except FtfofError as err:
            print(f"error: {err}", file=sys.stderr)
            raise typer.Exit(code=err.exit_code) from None
        except KeyboardInterrupt:
            out = kwargs.get("out")
            print(interrupted(command, out if isinstance(out, Path) else None), file=sys.stderr)
            raise typer.Exit(code=INTERRUPTED) from None
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)

    return wrapper
