"""The acquisition table: one row per simulated (or imported) sample, with its force series.

Series are variable-length ``list<float32>`` columns at the sensor rate (a failed sample keeps its
partial series for diagnosis); per-sample figures are float64 columns; control points are NaN
for trajectories that are not three-segment Beziers (the baselines, imported logs).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import pyarrow as pa

from ftfof.data.schema import field
from ftfof.errors import DataError, SimulationError
from ftfof.sim.film import FilmLimit
from ftfof.sim.records import CHANNELS, SampleResult, Status
from ftfof.sim.spec import Bench, SampleSpec
from ftfof.trajectory.bezier import DECISION_NAMES

SCALARS = (
    ("peak_detachment", "N", "max Fd over the trajectory and landing"),
    ("peak_normal", "N", "max pad tension normal to the wall while the pad holds"),
    ("peak_shear", "N", "max |Fx_pad| while the pad holds"),
    ("peak_pull", "N", "max |(Fx_pad, max(Fz_pad, 0))| while the pad holds: the foot's pull"),
    ("peak_pre_pressure", "N", "max Fp over the trajectory and landing (from the initial press)"),
    ("landing_pre_pressure", "N", "max Fp after the photoelectric switch"),
    ("initial_pre_pressure", "N", "mean press force just before the trajectory"),
    ("peak_body_acc", "m/s^2", "max IMU acceleration: body jitter"),
    ("min_bend_radius", "m", "1 / max film_curvature from the trajectory start"),
    ("max_clearance", "m", "highest the whole pad rose above the wall: max film_clearance"),
    ("switch_time", "s", "photoelectric switch: all bonds broken, pad above the switch"),
    ("bonds_at_end", "", "bonds intact at the end of the hold"),
    ("rebond_fraction", "", "bonded share of the pad's area when the landing hold ends"),
    ("proof_pull", "N", "F_proof pulled after the landing hold (NaN: no proof pull)"),
    ("held_pull", "N", "largest pull borne before a tenth of the pad let go, at most F_proof"),
    ("proof_held", "", "1 if the landed pad held F_proof through the proof hold, else 0"),
    ("steps", "", "solver steps"),
    ("retries", "", "1 if the solver needed a second, more careful attempt"),
)
UNITS = {
    "t": "s",
    "x_cmd": "m",
    "z_cmd": "m",
    "x_foot": "m",
    "z_foot": "m",
    "Fx": "N",
    "Fz": "N",
    "Fx_pad": "N",
    "Fz_pad": "N",
    "Fd": "N",
    "Fp": "N",
    "body_acc": "m/s^2",
    "bonds": "",
    "switch": "",
    "film_curvature": "1/m",
    "film_clearance": "m",
}

ACQUISITION = pa.schema(
    [
        field("key", pa.string(), "", "source:sample_id, unique"),
        field(
            "source",
            pa.string(),
            "",
            "sampled | baseline:<name> | optimum | front | imported | fine:<source>",
        ),
        field("sample_id", pa.int64(), "", "row of data/trajectories.parquet for sampled"),
        field("robot", pa.string(), "", "robot preset"),
        field("surface", pa.string(), "", "surface preset (or the log's label)"),
        field("status", pa.string(), "", " | ".join(Status)),
        field("error", pa.string(), "", "why a sample failed"),
        *[
            field(n, pa.float64(), "m", f"control point {n} (NaN if not a Bezier)")
            for n in DECISION_NAMES
        ],
        field("T3", pa.float64(), "s", "trajectory duration"),
        *[field(name, pa.float64(), unit, doc) for name, unit, doc in SCALARS],
        *[
            field(c, pa.list_(pa.float32()), UNITS[c], f"series {c} at the sensor rate")
            for c in CHANNELS
        ],
    ]
)


# the columns an acquisition's summary reads
SUMMARIZED = (
    "source",
    "status",
    "wall_time",
    "peak_detachment",
    "peak_pre_pressure",
    "landing_pre_pressure",
    "peak_body_acc",
    "min_bend_radius",
    "max_clearance",
    "held_pull",
    "proof_held",
)

# In-progress parts also carry each sample's wall time; the final table leaves it out so that
# re-running gives byte-identical data (the times go to a report instead).
PENDING = ACQUISITION.append(field("wall_time", pa.float64(), "s", "simulation wall time"))


def sampled_specs(
    on: Bench, table: pa.Table, robot: str, where: str, limit: int | None = None
) -> tuple[list[SampleSpec], dict[str, np.ndarray]]:
    """Specs of a trajectory table's first ``limit`` rows (all: None), source ``sampled`` with
    the row's sample id, and their decision vectors by key; a table (at ``where``) holding
    another robot's trajectories is refused."""
    robots = set(table.column("robot").to_pylist())
    if robots and robots != {robot}:
        raise DataError(
            where,
            f"holds trajectories of {sorted(robots)} but params select robot {robot!r} "
            "(re-run `ftfof sample`)",
        )
    if limit is not None:
        table = table.slice(0, limit)
    X = np.column_stack([table.column(n).to_numpy() for n in DECISION_NAMES])
    ids = table.column("sample_id").to_numpy()
    specs = [on.bezier("sampled", int(i), x) for i, x in zip(ids, X, strict=True)]
    return specs, {s.key: x for s, x in zip(specs, X, strict=True)}


def canonical_rows(table: pa.Table, keys: set[str]) -> pa.Table:
    """The rows of ``keys`` sorted by key: a job's samples in an order that does not depend on
    the order they completed in."""
    table = table.filter(pa.compute.is_in(table.column("key"), pa.array(sorted(keys))))
    order = np.argsort(np.array(table.column("key").to_pylist(), dtype=object), kind="stable")
    return table.take(pa.array(order))


def check_complete(table: pa.Table, expected: int, where: str) -> None:
    """A finished job's rows (at ``where``) must be ``expected`` distinct samples."""
    keys = table.column("key").to_pylist()
    if len(set(keys)) != len(keys) or len(keys) != expected:
        raise SimulationError(
            where, f"expected {expected} distinct samples, found {len(set(keys))}"
        )


def check_failures(table: pa.Table, max_rate: float) -> None:
    """At most ``max_rate`` of a job's samples may fail; more is an error naming the first."""
    status = np.array(table.column("status").to_pylist())
    failed = int(np.sum(status != "ok"))
    rate = failed / max(table.num_rows, 1)
    if rate > max_rate:
        errors = [e for e in table.column("error").to_pylist() if e][:3]
        raise SimulationError(
            "acquire",
            f"{failed} of {table.num_rows} samples failed ({rate:.1%} > acquire.max_failure_rate "
            f"{max_rate:.1%}); first errors: {errors}",
        )


def to_table(
    results: Sequence[SampleResult],
    robot: str,
    surface: str,
    controls: dict[str, np.ndarray],
    duration: float,
    with_wall_time: bool = True,
) -> pa.Table:
    """Rows for ``results`` (PENDING schema, or ACQUISITION without wall times); ``controls``
    maps a result key to its 12 decision values."""
    target = PENDING if with_wall_time else ACQUISITION
    cols: dict[str, list] = {f.name: [] for f in target}
    nan12 = np.full(12, np.nan)
    for r in results:
        cols["key"].append(r.key)
        cols["source"].append(r.source)
        cols["sample_id"].append(r.sample_id)
        cols["robot"].append(robot)
        cols["surface"].append(surface)
        cols["status"].append(str(r.status))
        cols["error"].append(r.error)
        if with_wall_time:
            cols["wall_time"].append(r.wall_time)
        X = controls.get(r.key, nan12)
        for j, name in enumerate(DECISION_NAMES):
            cols[name].append(float(X[j]))
        cols["T3"].append(duration)
        for name, _, _ in SCALARS:
            cols[name].append(float(r.scalars.get(name, np.nan)))
        for c in CHANNELS:
            cols[c].append(np.asarray(r.channels.get(c, []), dtype=np.float32))
    return pa.Table.from_pydict(cols, schema=target)


def summarize(
    table: pa.Table, film: FilmLimit, clearance: float, wall: float, simulated: int
) -> dict[str, object]:
    """An acquisition's metrics: its failures and time (``wall`` seconds, ``simulated`` runs by
    this invocation), the sampled set's peaks, the fraction bending the film below fc or never
    clearing the wall by ``clearance``, and each baseline's figures."""
    df = table.select(list(SUMMARIZED)).to_pandas()
    ok = df[df.status == "ok"]
    sampled = ok[ok.source == "sampled"]

    def stats(col: str) -> dict[str, float]:
        v = sampled[col].to_numpy()
        v = v[~np.isnan(v)]  # a figure not measured (no proof pull): no statistic
        if not len(v):
            return {}
        return {
            k: round(float(f(v)), 4)
            for k, f in (("mean", np.mean), ("std", np.std), ("min", np.min), ("max", np.max))
        }

    def below(col: str, value: float) -> float | None:
        return round(float(np.mean(sampled[col] < value)), 4) if len(sampled) else None

    return {
        "samples": len(df),
        "ok": len(ok),
        "failed": int(len(df) - len(ok)),
        "failure_rate": round(float((len(df) - len(ok)) / max(len(df), 1)), 4),
        "seconds_per_sample": round(float(df.wall_time.mean()), 4),
        "simulated_now": simulated,
        "wall_seconds": round(wall, 2),
        "peak_detachment": stats("peak_detachment"),
        "peak_pre_pressure": stats("peak_pre_pressure"),
        "peak_body_acc": stats("peak_body_acc"),
        # fraction of the sampled set bending the film tighter than fc, the film's limit
        "film_below_min_bend_radius": below("min_bend_radius", film.fc),
        "film_limit": film.as_dict(),
        "min_bend_radius": stats("min_bend_radius"),
        # fraction of the sampled set whose pad never rose foot.swing_clearance above the wall
        "pad_below_swing_clearance": below("max_clearance", clearance),
        "max_clearance": stats("max_clearance"),
        # the proof pull: the fraction of the sampled landings that held F_proof (None: no pull)
        "holds_fraction": (
            round(float((sampled.proof_held == 1.0).mean()), 4)
            if len(sampled) and sampled.proof_held.notna().all()
            else None
        ),
        "held_pull": stats("held_pull"),
        "baselines": _baseline_figures(ok),
    }


def _baseline_figures(ok: pd.DataFrame) -> dict[str, dict[str, float]]:
    """Each successful baseline's peaks, bend radius and clearance, by baseline name."""
    return {
        row.source.removeprefix("baseline:"): {
            "peak_detachment": round(float(row.peak_detachment), 4),
            "peak_pre_pressure": round(float(row.peak_pre_pressure), 4),
            "peak_body_acc": round(float(row.peak_body_acc), 4),
            "min_bend_radius": round(float(row.min_bend_radius), 6),
            "max_clearance": round(float(row.max_clearance), 6),
        }
        for row in ok[ok.source.str.startswith("baseline:")].itertuples()
    }
