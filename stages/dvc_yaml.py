"""`ftfof dvc-yaml`: write dvc.yaml from the catalog, the stages' params and the import graph
(:mod:`ftfof.pipeline.dvcfile`), or with ``--check`` say whether the committed one drifted."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from stages.common import console, stage


@stage
def command(
    out: Annotated[Path, typer.Option(help="The file to write.")] = Path("dvc.yaml"),
    check: Annotated[
        bool, typer.Option(help="Write nothing; exit 1 if the file differs from what it would be.")
    ] = False,
) -> None:
    """Write dvc.yaml: every stage's command, params, artefacts and code dependencies."""
    from ftfof.files import atomic_path
    from ftfof.pipeline.dvcfile import render

    text = render()
    if check:
        same = out.exists() and out.read_text() == text
        console.print(f"{out} is {'current' if same else 'stale: run `ftfof dvc-yaml`'}")
        if not same:
            raise typer.Exit(1)
        return
    with atomic_path(out) as tmp:
        tmp.write_text(text)
    console.print(f"wrote {out} ({len(text.splitlines())} lines)")
