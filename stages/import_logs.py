"""`ftfof import-logs`: force logs from a physical platform -> data/imported/*.parquet."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline import catalog
from stages.common import ParamsOption, console, stage

OUT = catalog.path("imported")


@stage
def command(
    logs: Annotated[list[Path], typer.Argument(help="CSV or Parquet log files.", exists=False)],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    out: Annotated[Path, typer.Option(help="Where imported samples go.")] = OUT,
    duration: Annotated[
        float | None, typer.Option(help="Trajectory duration T3 in s (default: the robot's).")
    ] = None,
) -> None:
    """Validate force logs and import them as samples the dataset stage trains on.

    Every file is checked before anything is written: a missing column, a non-increasing time,
    a missing or non-numeric value or an unknown unit stops the import naming file, row and column.
    """
    import pandas as pd
    import pyarrow.parquet as pq

    from ftfof.data.acquisition import to_table
    from ftfof.data.logs import parse
    from ftfof.errors import DataError
    from ftfof.files import write_parquet
    from ftfof.pipeline.bench import context_of
    from ftfof.pipeline.params_file import load_params

    params = load_params(params_path)
    T3 = duration if duration is not None else params.selected_robot.timing.T3
    max_speed = float(max(context_of(params).limits.velocity))
    tables = []
    names = [p.stem for p in logs]
    if len(set(names)) != len(names):
        raise DataError("import-logs", "two logs share a file name; rename one")
    for i, path in enumerate(logs):
        if not path.is_file():
            raise DataError(str(path), "no such file")
        try:
            if path.suffix.lower() == ".parquet":
                df = pq.read_table(path).to_pandas()
            else:
                df = pd.read_csv(path)
        except Exception as err:  # any reader failure is a malformed file
            raise DataError(str(path), f"unreadable ({str(err).splitlines()[0]})") from None
        result = parse(df, params.logs, str(path), path.stem, i, T3, max_speed)
        tables.append(
            to_table([result], params.robot, params.logs.surface, {}, T3, with_wall_time=False)
        )
    for path, table in zip(logs, tables, strict=True):
        write_parquet(out / f"{path.stem}.parquet", table)
    console.print(f"imported {len(tables)} log(s) into {out}")
