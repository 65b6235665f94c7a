"""The Table I analogue: peak forces and body jitter per trajectory, % change against a reference.

FTFOF Table I compares the optimum with the common trajectories on the platform; here every value
comes from the simulator, never from the surrogates.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

Column = tuple[str, str, str]  # (column of the acquisition table, label, unit)
# The three figures of FTFOF Table I.
PEAKS: tuple[Column, ...] = (
    ("peak_detachment", "max detachment force", "N"),
    ("peak_pre_pressure", "max pre-pressure", "N"),
    ("peak_body_acc", "max body jitter", "m/s²"),
)
# What the paper's table does not show but a robot engineer checks: how the pad is pulled off
# (resultant, normal, shear, while it holds) and how tightly the film is bent.
# ``jitter`` is the paper's IMU jitter taken where the paper takes it, during detachment (lift-off
# -> complete detachment + 50 ms: fsj), not over press, swing and landing like peak_body_acc.
FOOT: tuple[Column, ...] = (
    ("peak_pull", "max pull (resultant)", "N"),
    ("peak_normal", "max normal pull", "N"),
    ("peak_shear", "max shear", "N"),
    ("jitter", "body jitter in detachment", "m/s²"),
    ("landing_pre_pressure", "landing pre-pressure", "N"),
    ("min_bend_radius", "min film bend radius", "m"),
)
COLUMNS: tuple[Column, ...] = PEAKS + FOOT
# After the landing (ftfof/sim/proof.py): the pad's bonded share when the landing hold ends, and
# the pull it held in the proof pull (F_proof where it held); only where the robot has a proof
# pull, so only beside COLUMNS where every compared run measured them.
LANDED: tuple[Column, ...] = (
    ("rebond_fraction", "landing re-bond", ""),
    ("held_pull", "pull held after landing", "N"),
)


@dataclass(frozen=True)
class TableRow:
    trajectory: str
    values: dict[str, float]  # per PEAKS column
    change: dict[str, float]  # % against the reference row (0 for the reference itself)


def table_one(
    peaks: Mapping[str, Mapping[str, float]],
    reference: str,
    columns: tuple[Column, ...] = PEAKS,
) -> list[TableRow]:
    """Rows in the given order; ``peaks[name][column]`` are the figures of ``columns``."""
    if reference not in peaks:
        raise ValueError(f"reference trajectory {reference!r} is not among {sorted(peaks)}")
    base = peaks[reference]
    for column, label, _ in columns:
        value = base.get(column, np.nan)
        if not np.isfinite(value) or value <= 0:
            raise ValueError(f"{reference}: {label} is {value}; no % change can be taken from it")
    rows = []
    for name, row in peaks.items():
        values = {c: float(row[c]) for c, _, _ in columns}
        change = {c: 100.0 * (values[c] - base[c]) / base[c] for c, _, _ in columns}
        rows.append(TableRow(name, values, change))
    return rows


# FTFOF Table I, measured on the MST-M3F platform (the paper's optimum under "optimal").
PAPER_TABLE_I: dict[str, dict[str, float]] = {
    "polynomial": {"peak_detachment": 7.49, "peak_pre_pressure": 5.41, "peak_body_acc": 327.27},
    "cycloidal": {"peak_detachment": 7.24, "peak_pre_pressure": 5.21, "peak_body_acc": 285.22},
    "random_bezier": {"peak_detachment": 6.11, "peak_pre_pressure": 5.85, "peak_body_acc": 141.30},
    "optimal": {"peak_detachment": 5.40, "peak_pre_pressure": 5.85, "peak_body_acc": 58.41},
}


NOT_CLIMBED = "not_climbed"  # the climbing table's trajectories the robot could not run, and why
MOVED = "moved_to"  # where the optimum fell: the candidate the choice moved to, and why
CLIMB_NOTES = (NOT_CLIMBED, MOVED)  # the climbing table's keys that are not a climb


def climb_record(
    climbs: Mapping[str, Mapping[str, Any]],
    skipped: Mapping[str, str],
    moved: Mapping[str, Any] | None = None,
) -> dict:
    """The climbing robot's runs as the report keeps them: per name its climb's figures to four
    decimals, as Table I's (flags and missing values as they are), its fall and error;
    ``not_climbed``, the trajectories it could not run and why; and ``moved_to`` where the
    optimum fell (:func:`ftfof.pipeline.climb.moved_choice`)."""
    out: dict[str, Any] = {
        n: {**_rounded(d["summary"]), "fall": d["fall"], "error": d["error"]}
        for n, d in climbs.items()
    }
    if skipped:
        out[NOT_CLIMBED] = dict(skipped)
    if moved is not None:
        out[MOVED] = dict(moved)
    return out


def climbs_of(record: Mapping[str, Any]) -> dict[str, Any]:
    """The climbing table's climbs by name, without its notes (CLIMB_NOTES)."""
    return {n: row for n, row in record.items() if n not in CLIMB_NOTES}


def moved_row(record: Mapping[str, Any]) -> int | None:
    """The front row the choice moved to where the optimum fell (None: it did not move, or no
    candidate climbed)."""
    return (record.get(MOVED) or {}).get("row")


def _rounded(figures: Mapping[str, Any]) -> dict[str, Any]:
    return {
        k: round(v, 4) if isinstance(v, float) and not isinstance(v, bool) else v
        for k, v in figures.items()
    }
