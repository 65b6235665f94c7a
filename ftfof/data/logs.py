"""Force logs from a physical acquisition platform -> samples in the acquisition format.

A log is one trajectory execution: a table with a time column, the foot position x, z in the
trajectory frame (origin at the foot's start point, z away from the wall) and the normal force Fz,
optionally the tangential force Fx. Column names and units come from the ``logs`` settings; a
header may also carry its unit in brackets, ``x [mm]``, which then wins. Every problem is raised
as a :class:`DataError` naming the file, the row (1-based, as in a spreadsheet, header = row 1)
and the column.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd

import ftfof.config as config
from ftfof.demand import LET_GO, REACHED
from ftfof.errors import DataError
from ftfof.sim.records import CHANNELS, SampleResult, Status, force_peaks

SCALE = {
    "time": {"s": 1.0, "ms": 1e-3},
    "length": {"m": 1.0, "mm": 1e-3, "um": 1e-6},
    "force": {"N": 1.0, "mN": 1e-3},
}
KIND = {"time": "time", "x": "length", "z": "length", "Fz": "force", "Fx": "force", "proof": "flag"}
OPTIONAL = ("Fx", "proof")  # a log may leave these out
HEADER = re.compile(r"^\s*(?P<name>[^\[\]]+?)\s*(?:\[(?P<unit>[^\]]*)\])?\s*$")


def _columns(df: pd.DataFrame, fmt: config.Logs, source: str) -> dict[str, tuple[str, float]]:
    """Map each quantity to (header, scale to SI); checks presence and units."""
    headers = {}
    for header in df.columns:
        m = HEADER.match(str(header))
        if m:
            headers[m.group("name")] = (str(header), m.group("unit"))
    wanted = fmt.columns.model_dump()
    out = {}
    for quantity, name in wanted.items():
        if name is None:
            continue
        if name not in headers:
            if quantity in OPTIONAL:
                continue
            raise DataError(source, f"row 1, column {name!r}: missing (needed for {quantity})")
        header, unit = headers[name]
        kind = KIND[quantity]
        if kind == "flag":  # no unit: nonzero or zero
            out[quantity] = (header, 1.0)
            continue
        unit = unit if unit is not None else getattr(fmt.units, kind)
        if unit not in SCALE[kind]:
            raise DataError(
                source,
                f"row 1, column {header!r}: unknown {kind} unit {unit!r} "
                f"(known: {', '.join(SCALE[kind])})",
            )
        out[quantity] = (header, SCALE[kind][unit])
    return out


def parse(
    df: pd.DataFrame,
    fmt: config.Logs,
    source: str,
    name: str,
    sample_id: int,
    duration: float | None = None,
    max_speed: float | None = None,
    proof_pull: float | None = None,
) -> SampleResult:
    """One validated log as the sample ``imported:<name>`` (channels in SI, tension positive).

    With the robot's trajectory ``duration`` (T3, s) and its leg's ``max_speed`` (m/s), a log
    whose time or length unit is off by a thousand is refused: it would import a step of a
    millisecond, or a foot at a hundred metres a second. A log whose ``proof`` column marks the
    platform's proof pull is judged against the robot's F_proof ``proof_pull``
    (:func:`proof_figures`), and its channels end where the pull begins, as a simulated
    record's do."""
    cols = _columns(df, fmt, source)
    values = _values(df, cols, source)
    if not fmt.tension_positive:
        values["Fz"] = -values["Fz"]
    values, proof = _proof_phase(values, cols, proof_pull, source)
    t = values["time"]
    if t.size < 2:
        raise DataError(source, "row 2: a log needs at least two rows")
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        header = cols["time"][0]
        raise DataError(source, f"row {back[0] + 3}, column {header!r}: time does not increase")
    if duration is not None and max_speed is not None:
        _plausible(t, values["x"], values["z"], cols, duration, max_speed, source)
    channels = _channels(values)
    assert set(channels) == set(CHANNELS)
    scalars = {
        "peak_detachment": float(channels["Fd"].max()),
        "peak_pre_pressure": float(channels["Fp"].max()),
        **force_peaks(channels["Fx_pad"], channels["Fz"], np.ones_like(t, dtype=bool)),
        **proof,
    }
    result = SampleResult(f"imported:{name}", "imported", sample_id, Status.OK, "", 0.0, channels)
    result.scalars = scalars
    return result


def _proof_phase(
    values: dict[str, np.ndarray],
    cols: dict[str, tuple[str, float]],
    force: float | None,
    source: str,
) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """The log's rows before its proof pull, and the pull's figures from its tension-positive
    Fz (none without the phase). The pull must run from its first marked row to the log's end."""
    flag = values.pop("proof", None)
    if flag is None or not flag.any():
        return values, {}
    header = cols["proof"][0]
    start = int(np.argmax(flag != 0))
    if not (flag[start:] != 0).all():
        stop = start + int(np.argmax(flag[start:] == 0))
        raise DataError(
            source, f"row {stop + 2}, column {header!r}: the proof pull must run to the log's end"
        )
    if start < 2:
        raise DataError(source, f"row {start + 2}, column {header!r}: the log is all proof pull")
    if force is None:
        raise DataError(
            source,
            f"column {header!r}: the log carries a proof pull, but the robot asks for none "
            "(robots.<name>.proof is null): there is no F_proof to judge it against",
        )
    return {k: v[:start] for k, v in values.items()}, proof_figures(values["Fz"][start:], force)


def proof_figures(tension: np.ndarray, force: float) -> dict[str, float]:
    """A logged proof pull's figures, from the sensor's tension alone (a force log does not see
    the bonds): it held when the tension reached REACHED x F_proof and never fell a tenth of
    F_proof below that after (a pad letting go drops the load the loop holds); ``held_pull`` is
    the largest tension borne, F_proof where it held."""
    reached = np.flatnonzero(tension >= REACHED * force)
    held = reached.size > 0 and float(tension[reached[0] :].min()) >= (REACHED - LET_GO) * force
    peak = float(tension.max())
    return {
        "proof_pull": force,
        "held_pull": force if held else min(peak, force),
        "proof_held": float(held),
        "rebond_fraction": np.nan,  # a force log does not see the bonds
    }


def _values(
    df: pd.DataFrame, cols: dict[str, tuple[str, float]], source: str
) -> dict[str, np.ndarray]:
    """Each quantity's column in SI; a cell that is not a finite number is refused by row."""
    values = {}
    for quantity, (header, scale) in cols.items():
        v = pd.to_numeric(df[header], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise DataError(source, f"row {bad[0] + 2}, column {header!r}: not a finite number")
        values[quantity] = v * scale
    return values


def _channels(values: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The acquisition channels of a log (its Fz already tension-positive): the commanded path
    is the measured one, and what a force log does not see is NaN."""
    t, fz = values["time"], values["Fz"]
    nan = np.full_like(t, np.nan)
    x, z = values["x"], values["z"]
    return {
        "t": t - t[0],
        "x_cmd": x,
        "z_cmd": z,
        "x_foot": x,
        "z_foot": z,
        "Fx": values.get("Fx", nan),
        "Fz": fz,
        "Fx_pad": values.get("Fx", nan),  # a real platform sees the pad through its sensor
        "Fz_pad": fz,
        "Fd": np.maximum(fz, 0.0),
        "Fp": np.maximum(-fz, 0.0),
        "body_acc": nan,
        "bonds": nan,
        "switch": nan,
        "film_curvature": nan,  # a force log does not see the film
        "film_clearance": nan,
    }


def _plausible(
    t: np.ndarray,
    x: np.ndarray,
    z: np.ndarray,
    cols: dict[str, tuple[str, float]],
    duration: float,
    max_speed: float,
    source: str,
) -> None:
    """Refuse a log whose span or foot speed is orders of magnitude off the robot's."""
    header = cols["time"][0]
    span = float(t[-1] - t[0])
    if not duration / 2 <= span <= 100 * duration:
        raise DataError(
            source,
            f"column {header!r}: the log spans {span:.4g} s against the robot's T3 = "
            f"{duration:g} s; its time unit looks wrong (set it in the header, e.g. 't [ms]', "
            "or in logs.units.time)",
        )
    speed = float(np.max(np.hypot(np.diff(x), np.diff(z)) / np.diff(t)))
    if speed > 10 * max_speed:
        raise DataError(
            source,
            f"columns {cols['x'][0]!r}, {cols['z'][0]!r}: the foot moves at {speed:.3g} m/s, "
            f"{speed / max_speed:.0f} times the leg's {max_speed:g} m/s; check the length and "
            "time units",
        )
