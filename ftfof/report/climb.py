"""The report's section on the climbing robot: each trajectory's climb beside its platform jitter
and, for the paper's robot, FTFOF Table I's IMU reading."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ftfof.evaluate.table import PAPER_TABLE_I, TableRow, climbs_of

# our Table I names -> the paper's (its "optimal" is the published optimum, simulated here as
# paper_optimum)
PAPER_NAMES = {
    "polynomial": "polynomial",
    "cycloidal": "cycloidal",
    "random_bezier": "random_bezier",
    "paper_optimum": "optimal",
}


def climb_rows(
    climbed: Mapping[str, Any], rows: Sequence[TableRow], steps: int, paper_robot: bool
) -> list[dict[str, Any]]:
    """One row per climbed trajectory, in Table I's order, then the candidates the choice moved
    through where the optimum fell: steps done, how it ended, its jitter
    (detachment window and whole step), the platform's jitter and proof pull held, and the
    paper's jitter where it has one."""
    platform = {r.trajectory: r.values.get("jitter") for r in rows}
    held = {r.trajectory: r.values.get("held_pull") for r in rows}
    climbs = climbs_of(climbed)
    order = [r.trajectory for r in rows if r.trajectory in climbs]
    order += [n for n in climbs if n not in order]  # the candidates climbed where the optimum fell
    out = []
    for name in order:
        c = climbs[name]
        paper = PAPER_TABLE_I.get(PAPER_NAMES.get(name, ""), {}).get("peak_body_acc")
        if c.get("error"):
            ended = f"failed: {c['error']}"
        elif c["fell"]:
            ended = f"fell: {c['fall']}"
        else:
            ended = "climbed"
        out.append(
            {
                "trajectory": name,
                "steps": f"{int(c['steps_done'])} of {steps}",
                "ended": ended,
                "fell": bool(c["fell"]) or bool(c.get("error")),
                "jitter": _number(c["jitter"]),
                "jitter_step": _number(c["jitter_step"]),
                "peak_pull": _number(c["peak_pull"]),
                "platform": _number(platform.get(name)),
                "platform_held_pull": _number(held.get(name)),
                "paper": paper if paper_robot else None,
            }
        )
    return out


def _number(value: float | None) -> float:
    """A figure for the table: NaN (shown as a dash) where none was measured."""
    return float("nan") if value is None else float(value)
