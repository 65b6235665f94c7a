"""The re-simulations as a table: which run is which (the optimum, a front member, a baseline,
the published optimum; at the check step or on the check film), and each one's Table I figures."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ftfof.data import targets
from ftfof.data.dataset import CHANNELS
from ftfof.errors import SimulationError
from ftfof.evaluate.film_check import FILM
from ftfof.evaluate.step_check import FINE
from ftfof.evaluate.table import COLUMNS, LANDED, TableRow, table_one
from ftfof.trajectory.baselines import BASELINE_NAMES

OPTIMUM = "optimum"
PAPER_OPTIMUM = "baseline:paper_optimum"  # the published optimum, simulated, never fitted
REPEAT = "repeat:"  # source prefix of a front member's repeatability runs (ftfof.evaluate.repeat)


def ok_rows(df: pd.DataFrame, reference: str) -> pd.DataFrame:
    """The simulations that succeeded; a clear error when the optimum or the reference failed."""
    for source in (OPTIMUM, f"baseline:{reference}"):
        row = df[df.source == source]
        if row.empty or row.iloc[0].status != "ok":
            error = row.iloc[0].error if not row.empty else "missing"
            raise SimulationError(source, f"re-simulation failed: {error}")
    return df[df.status == "ok"]


def split_runs(
    simulations: pd.DataFrame,
) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """The runs as the acquisition makes them, those at the check step and those on the check
    film (each with its ``FINE`` / ``FILM`` prefix removed from the source), and the front
    members' repeatability runs (their sources as they are)."""
    fine = simulations.source.str.startswith(FINE)
    film = simulations.source.str.startswith(FILM)
    repeat = simulations.source.str.startswith(REPEAT)
    check, on_film = simulations[fine], simulations[film]
    return (
        simulations[~fine & ~film & ~repeat],
        check.assign(source=check.source.str.removeprefix(FINE)),
        on_film.assign(source=on_film.source.str.removeprefix(FILM)),
        simulations[repeat],
    )


def run_name(source: str, sample_id: int) -> str:
    """A run's name across checks: Table I's name, or ``front <row>`` for a front member."""
    return f"front {sample_id}" if source == "front" else table_name(source)


def compared(df: pd.DataFrame, reference: str) -> dict[str, pd.Series]:
    """By display name, the rows of the table and the figures: the reference, the other
    baselines, the paper's published optimum (where the robot has one), then our optimum."""
    present = set(df.source)
    baselines = [f"baseline:{n}" for n in BASELINE_NAMES if f"baseline:{n}" in present]
    first = f"baseline:{reference}"
    sources = [first, *(s for s in baselines if s != first)]
    sources += [s for s in df.source if s == PAPER_OPTIMUM] + [OPTIMUM]
    return {table_name(s): df[df.source == s].iloc[0] for s in sources}


def table_name(source: str) -> str:
    """A simulation's name in Table I: its source without the ``baseline:`` prefix."""
    return source.removeprefix("baseline:")


def figures_of(row: pd.Series, T3: float) -> dict[str, float]:
    """One simulation's Table I figures: the acquisition's scalars and the detachment jitter."""
    out = {c: float(row[c]) for c, _, _ in COLUMNS if c != "jitter"}
    out["jitter"] = float(np.max(targets.full_rate(channels(row), T3)["body_acc"]))
    return out | {c: float(row.get(c, np.nan)) for c, _, _ in LANDED}


def table_rows(df: pd.DataFrame, reference: str, T3: float) -> list[TableRow]:
    """The Table I analogue, with the foot's pull and film figures, against ``reference``."""
    peaks = {name: figures_of(row, T3) for name, row in compared(df, reference).items()}
    rows = table_one(peaks, reference, COLUMNS)
    if all(np.isfinite(f[c]) for f in peaks.values() for c, _, _ in LANDED):
        base = peaks[reference]
        for row in rows:  # a landing can hold nothing: no % change from a reference of 0
            for c, _, _ in LANDED:
                value = peaks[row.trajectory][c]
                row.values[c] = value
                row.change[c] = 100.0 * (value - base[c]) / base[c] if base[c] > 0 else np.nan
    return rows


def simulated_rows(df: pd.DataFrame) -> pd.DataFrame:
    """The re-simulated optimum, then the front members by row: the order of every per-member
    result (:func:`front_members`, :func:`fidelity_of`)."""
    sims = df[df.source.isin([OPTIMUM, "front"])]
    return sims.assign(first=sims.source != OPTIMUM).sort_values(["first", "sample_id"])


def channels(row: pd.Series) -> dict[str, np.ndarray]:
    """The full-rate channels the surrogate's targets are made of, as float arrays."""
    return {c: np.asarray(row[c], dtype=float) for c in CHANNELS}
