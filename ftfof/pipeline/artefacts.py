"""How the stages' artefacts are read and written, one reader and one writer per format
(:mod:`ftfof.pipeline.catalog` names where each lives): the optimum and its front, the refinement
report and the stages' figures. A file from another robot or an older ftfof is refused by name."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pyarrow.parquet as pq

from ftfof.config import Optimize
from ftfof.digests import file_sha256, models_digest
from ftfof.errors import DataError
from ftfof.evaluate.run import Inputs
from ftfof.files import atomic_dir
from ftfof.optimize.select import Outcome, front_table, missing_fields, optimum_record
from ftfof.pipeline.catalog import run_first, writer_of
from ftfof.robot import RobotContext

OPTIMUM_FILE = "optimum.json"  # the chosen row, RHS's steps and the simulator's verdicts
FRONT_FILE = "front.parquet"  # the front, the nominees and the polished rows, one per row


def optimum_digest(directory: Path) -> str:
    """Names an optimum: the run that wrote it carries it, the runs that read it look it up."""
    return file_sha256(directory / OPTIMUM_FILE, 16)


def write_optimum(
    out: Path, outcome: Outcome, ctx: RobotContext, digest: str, cfg: Optimize
) -> None:
    """``front.parquet`` and ``optimum.json`` in ``out``, all or nothing: what evaluate reads.
    ``digest`` names the surrogates that predicted the front's objectives."""
    with atomic_dir(out) as tmp:
        pq.write_table(front_table(outcome, ctx, digest), tmp / FRONT_FILE)
        optimum = optimum_record(outcome, ctx, cfg, digest)
        (tmp / OPTIMUM_FILE).write_text(json.dumps(optimum, indent=2, sort_keys=True) + "\n")


# What a stage reads from an optimum.json (dotted: inside a section). A file from an older
# ftfof that lacks one is refused by name, not with a KeyError deep in the stage.
POLISH_READS = ("robot", "front_row", "models_digest", "simulator_check")
EVALUATE_READS = (*POLISH_READS, "origin", "decision", "rhs.rows", "rhs.steps")


def read_optimum(directory: Path, robot: str, fields: Sequence[str] = EVALUATE_READS) -> Inputs:
    """The optimum and its front, checked to be of ``robot`` and to hold ``fields``; any problem
    is one DataError."""
    path = directory / OPTIMUM_FILE
    if not path.exists() or not (directory / FRONT_FILE).exists():
        raise DataError(str(directory), f"no optimum ({run_first(directory, 'optimize')})")
    try:
        optimum = json.loads(path.read_text())
        front = pq.read_table(directory / FRONT_FILE)
        meta = json.loads(front.schema.metadata[b"ftfof"])
    except (ValueError, KeyError, OSError) as err:
        raise DataError(str(directory), f"unreadable optimize output ({err})") from None
    missing = missing_fields(optimum, fields)
    if missing:
        raise DataError(
            str(path),
            f"lacks {', '.join(missing)}: written by an older ftfof "
            f"(re-run `ftfof {writer_of(directory) or 'optimize'}`)",
        )
    if optimum.get("robot") != robot or meta.get("robot") != robot:
        raise DataError(
            str(directory),
            f"holds an optimum for {optimum.get('robot')!r} but params select {robot!r} "
            f"(re-run `ftfof {writer_of(directory) or 'optimize'}`)",
        )
    frame = front.to_pandas().set_index("row")
    return Inputs(optimum, frame, list(meta["objectives"]), optimum_digest(directory))


def read_refine(path: Path) -> list[dict]:
    """The rounds of reports/refine.json (empty with ``refine.rounds: 0``)."""
    if not path.exists():
        raise DataError(str(path), f"no refinement report ({run_first(path, 'refine')})")
    try:
        return list(json.loads(path.read_text())["rounds"])
    except (ValueError, KeyError, TypeError) as err:
        raise DataError(str(path), f"unreadable refinement report ({err})") from None


def check_models(inputs: Inputs, directory: Path, models: Path) -> None:
    """The optimum in ``directory`` must have been found on the surrogates in ``models``."""
    if not models.is_dir():
        raise DataError(str(models), f"no trained models ({run_first(models, 'train')})")
    if inputs.optimum["models_digest"] != models_digest(models):
        raise DataError(str(directory), f"was optimised on other models than {models} (re-run it)")


def read_json(path: Path) -> Any:
    """A stage's JSON report, for the report that gathers it."""
    if not path.exists():
        raise DataError(str(path), f"missing ({run_first(path, 'the stage that writes it')})")
    try:
        return json.loads(path.read_text())
    except ValueError as err:
        raise DataError(str(path), f"unreadable JSON ({err})") from None


def read_figure(path: Path) -> str:
    """A stage's PNG as a data URI for the self-contained report."""
    from ftfof.report.html import png_data_uri

    if not path.exists():
        writer = writer_of(path)
        hint = f"run `ftfof {writer}` first" if writer else "run the stage that writes it"
        raise DataError(str(path), f"figure missing ({hint})")
    try:
        return png_data_uri(path.read_bytes())
    except ValueError:
        raise DataError(str(path), "is not a PNG image") from None
