"""The stages' progress bars: the time left at the mean pace, and rows in a log."""

from __future__ import annotations

import io

from rich.console import Console
from rich.progress import TextColumn

from ftfof.pipeline import console as stderr
from ftfof.pipeline.console import Bars, TimeLeftColumn


def _bars(clock: list[float], terminal: bool) -> tuple[Bars, io.StringIO]:
    out = io.StringIO()
    log = Console(file=out, force_terminal=terminal, width=120)
    bars = Bars(TextColumn("{task.description}"), TimeLeftColumn(), console=log,
                get_time=lambda: clock[0])  # fmt: skip
    return bars, out


def _left(bars: Bars, task) -> str:
    return TimeLeftColumn().render(bars.tasks[task]).plain


def test_the_time_left_follows_the_mean_pace_since_the_start_past_resumed_steps():
    clock = [100.0]
    bars, _ = _bars(clock, terminal=True)
    task = bars.add_task("climbs", total=10, completed=4, resumed=4)
    assert _left(bars, task) == "-:--:-- left"  # nothing done in this run yet
    clock[0] = 160.0  # two of this run's six in a minute: the other four in two
    bars.update(task, advance=2)
    assert _left(bars, task) == "0:02:00 left"
    fresh = bars.add_task("polish", total=3)
    clock[0] = 190.0
    bars.update(fresh, completed=1)
    assert _left(bars, fresh) == "0:01:00 left"


def test_in_a_log_a_bar_prints_its_row_at_once_and_then_every_log_every_seconds(monkeypatch):
    now = [1000.0]
    monkeypatch.setattr(stderr.time, "monotonic", lambda: now[0])
    bars, out = _bars([0.0], terminal=False)
    with bars:
        task = bars.add_task("polish", total=28)
        bars.update(task, completed=1)
        bars.advance(task)  # within LOG_EVERY: not printed
        now[0] += stderr.LOG_EVERY
        bars.update(task, completed=3)
    rows = [line for line in out.getvalue().splitlines() if line.startswith("polish")]
    assert len(rows) == 3  # two logged, and rich's own final row
    assert all("left" in row for row in rows)


def test_a_terminal_gets_the_live_bar_only():
    bars, out = _bars([0.0], terminal=True)
    bars.update(bars.add_task("acquire", total=5), completed=1)
    assert out.getvalue() == ""  # not started: a terminal's bar is drawn by rich's Live
