"""The pipeline's stderr: one console for messages and progress bars, shared by every stage."""

from __future__ import annotations

import time
from datetime import timedelta
from typing import Any

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    ProgressColumn,
    Task,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
)
from rich.text import Text

console = Console(stderr=True)
LOG_EVERY = 30.0  # s between a bar's rows printed where stderr is not a terminal


class TimeLeftColumn(ProgressColumn):
    """The time left at the mean pace since the task began (past its ``resumed`` steps, those
    done before this run). rich's own column paces on the last 30 s and two updates: a climb or
    a polish generation can outlast that, and a pool's first results arrive together."""

    def render(self, task: Task) -> Text:
        done = task.completed - task.fields.get("resumed", 0)
        elapsed = task.elapsed or 0.0
        if task.total is None or done <= 0 or elapsed <= 0:
            return Text("-:--:-- left", style="progress.remaining")
        left = max(task.total - task.completed, 0) * elapsed / done
        return Text(f"{timedelta(seconds=round(left))} left", style="progress.remaining")


class Bars(Progress):
    """rich's Progress, which draws nothing into a log until it ends: where stderr is not a
    terminal, a task's row is printed at its first update and then every ``LOG_EVERY`` s."""

    logged = float("-inf")

    def update(self, task_id: TaskID, **kwargs: Any) -> None:
        super().update(task_id, **kwargs)
        self._log(task_id)

    def advance(self, task_id: TaskID, advance: float = 1) -> None:
        super().advance(task_id, advance)
        self._log(task_id)

    def _log(self, task_id: TaskID) -> None:
        now = time.monotonic()
        if self.console.is_terminal or now - self.logged < LOG_EVERY:
            return
        self.logged = now
        self.console.print(self.make_tasks_table([self._tasks[task_id]]))


def progress(description: str) -> Progress:
    """A rich progress bar on stderr: done of total, an info field, time taken and time left.
    A task added with ``completed`` steps done before (a resumed job) passes ``resumed`` too."""
    return Bars(
        TextColumn(f"[bold]{description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[info]}"),
        TimeElapsedColumn(),
        TimeLeftColumn(),
        console=console,
        transient=False,
    )
