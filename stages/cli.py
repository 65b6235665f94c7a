"""The `ftfof` command: one typer app, one sub-command per pipeline stage and tool."""

from __future__ import annotations

import os

import typer

from stages import (
    acquire,
    calibrate,
    dataset,
    evaluate,
    import_logs,
    optimize,
    polish,
    profile,
    refine,
    sample,
    simulate,
    sweep,
    train,
)
from stages.runtime import tune_allocator

os.environ.setdefault("MLFLOW_DISABLE_TELEMETRY", "true")
os.environ.setdefault("DVC_NO_ANALYTICS", "true")

app = typer.Typer(
    name="ftfof",
    help="Foot Trajectory and Force Optimization Framework: the pipeline's stages and tools.",
    no_args_is_help=True,
    pretty_exceptions_show_locals=False,
    add_completion=False,
)


@app.callback()
def _root() -> None:
    """Run a stage by name; `dvc repro` runs them all in order (see dvc.yaml)."""


app.command("sample")(sample.command)
app.command("acquire")(acquire.command)
app.command("dataset")(dataset.command)
app.command("import-logs")(import_logs.command)
app.command("train")(train.command)
app.command("optimize")(optimize.command)
app.command("refine")(refine.command)
app.command("polish")(polish.command)
app.command("evaluate")(evaluate.command)
app.command("profile")(profile.command)
app.command("simulate")(simulate.command)
app.command("calibrate")(calibrate.command)
app.command("sweep")(sweep.command)


def main() -> None:
    tune_allocator()
    app(prog_name="ftfof")
