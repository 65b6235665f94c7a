"""The `ftfof` command: one typer app, one sub-command per pipeline stage and tool."""

from __future__ import annotations

import os
from typing import Annotated

import typer

from stages import (
    acquire,
    calibrate,
    climb,
    climb_table,
    dataset,
    dvc_yaml,
    evaluate,
    export,
    identify,
    import_logs,
    optimize,
    payload,
    polish,
    profile,
    refine,
    sample,
    simulate,
    slip,
    slip_test,
    study,
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
    # plain help: it wraps long option values instead of cutting them at the terminal's width
    rich_markup_mode=None,
)


def _version(shown: bool) -> None:
    if shown:
        from importlib.metadata import version

        from ftfof.version import __version__

        print(f"ftfof {__version__} (exudyn {version('exudyn')}, torch {version('torch')})")
        raise typer.Exit


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version, is_eager=True, help="Print the version."),
    ] = False,
) -> None:
    """Run a stage by name; `dvc repro` runs them all in order (see dvc.yaml)."""


app.command("sample")(sample.command)
app.command("acquire")(acquire.command)
app.command("dataset")(dataset.command)
app.command("import-logs")(import_logs.command)
app.command("train")(train.command)
app.command("optimize")(optimize.command)
app.command("refine")(refine.command)
app.command("polish")(polish.command)
app.command("climb-table")(climb_table.command)
app.command("slip")(slip.command)
app.command("evaluate")(evaluate.command)
app.command("profile")(profile.command)
app.command("simulate")(simulate.command)
app.command("export")(export.command)
app.command("climb")(climb.command)
app.command("calibrate")(calibrate.command)
app.command("slip-test")(slip_test.command)
app.command("identify")(identify.command)
app.command("sweep")(sweep.command)
study.app.command("payload")(payload.command)  # not a stage: study.py imports no climb
app.add_typer(study.app, name="study")
app.command("dvc-yaml")(dvc_yaml.command)


def main() -> None:
    tune_allocator()
    app(prog_name="ftfof")
