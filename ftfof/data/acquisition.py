"""The acquisition table: one row per simulated (or imported) sample, with its force series.

Series are variable-length ``list<float32>`` columns at the sensor rate (a failed sample keeps its
partial series for diagnosis); per-sample figures are float64 columns; control points are NaN
for trajectories that are not three-segment Beziers (the baselines, imported logs).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pyarrow as pa

from ftfof.data.schema import field
from ftfof.sim.records import CHANNELS, SampleResult, Status
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


# In-progress parts also carry each sample's wall time; the final table leaves it out so that
# re-running gives byte-identical data (the times go to a report instead).
PENDING = ACQUISITION.append(field("wall_time", pa.float64(), "s", "simulation wall time"))


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
