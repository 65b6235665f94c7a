"""`ftfof import-logs`: force logs from a physical platform -> data/imported/*.parquet, or slip
logs (`--protocol slip`) -> data/slip/*.csv for `ftfof identify`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ftfof.pipeline import catalog
from stages.common import ParamsOption, console, stage

OUT = catalog.path("imported")
SLIP_OUT = catalog.path("slip_logs")
PROTOCOLS = ("peel", "slip")
OutOption = typer.Option(help=f"Where they go (default: {OUT}, or {SLIP_OUT} for slip logs).")
DurationOption = typer.Option(help="Trajectory duration T3 in s (default: the robot's).")
ProtocolOption = typer.Option(
    help="peel: a step's force log (a training sample); slip: a slip test's log "
    "(t, Fx, Fz, load) for `ftfof identify --log`."
)


@stage
def command(
    logs: Annotated[list[Path], typer.Argument(help="CSV or Parquet log files.", exists=False)],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    out: Annotated[Path | None, OutOption] = None,
    duration: Annotated[float | None, DurationOption] = None,
    protocol: Annotated[str, ProtocolOption] = "peel",
) -> None:
    """Validate force logs and import them: peel logs as samples the dataset stage trains on,
    slip logs as the logs `ftfof identify` estimates a surface from.

    Every file is checked before anything is written: a missing column, a non-increasing time,
    a missing or non-numeric value or an unknown unit (a slip log: too few slip samples) stops
    the import naming file, row and column.
    """
    from ftfof.data.acquisition import to_table
    from ftfof.data.logs import parse
    from ftfof.demand import proof_pull
    from ftfof.errors import DataError
    from ftfof.files import write_parquet
    from ftfof.pipeline.bench import context_of
    from ftfof.pipeline.params_file import load_params

    if protocol not in PROTOCOLS:
        raise DataError(
            "--protocol", f"unknown protocol {protocol!r} (have {', '.join(PROTOCOLS)})"
        )
    frames = _read(logs)
    if protocol == "slip":
        _import_slip(logs, frames, out or SLIP_OUT)
        return
    out = out or OUT
    params = load_params(params_path)
    T3 = duration if duration is not None else params.selected_robot.timing.T3
    max_speed = float(max(context_of(params).limits.velocity))
    force = proof_pull(params.selected_robot)  # F_proof, where a log carries the proof pull
    tables = []
    for i, (path, df) in enumerate(zip(logs, frames, strict=True)):
        result = parse(df, params.logs, str(path), path.stem, i, T3, max_speed, force)
        tables.append(
            to_table([result], params.robot, params.logs.surface, {}, T3, with_wall_time=False)
        )
    for path, table in zip(logs, tables, strict=True):
        write_parquet(out / f"{path.stem}.parquet", table)
    console.print(f"imported {len(tables)} log(s) into {out}")


def _read(logs: list[Path]) -> list[Any]:
    """Every log as a DataFrame, or a one-line error naming the file."""
    import pandas as pd
    import pyarrow.parquet as pq

    from ftfof.errors import DataError

    names = [p.stem for p in logs]
    if len(set(names)) != len(names):
        raise DataError("import-logs", "two logs share a file name; rename one")
    frames = []
    for path in logs:
        if not path.is_file():
            raise DataError(str(path), "no such file")
        try:
            if path.suffix.lower() == ".parquet":
                frames.append(pq.read_table(path).to_pandas())
            else:
                frames.append(pd.read_csv(path))
        except Exception as err:  # any reader failure is a malformed file
            raise DataError(str(path), f"unreadable ({str(err).splitlines()[0]})") from None
    return frames


def _import_slip(logs: list[Path], frames: list[Any], out: Path) -> None:
    """Slip logs, all validated first, written as `identify --log` reads them."""
    import pandas as pd

    from ftfof.data.sliplog import parse_slip
    from ftfof.files import atomic_path

    parsed = [parse_slip(df, str(path)) for path, df in zip(logs, frames, strict=True)]
    out.mkdir(parents=True, exist_ok=True)
    for path, log in zip(logs, parsed, strict=True):
        with atomic_path(out / f"{path.stem}.csv") as tmp:
            pd.DataFrame(log.columns()).to_csv(tmp, index=False)
    console.print(f"imported {len(parsed)} slip log(s) into {out}")
