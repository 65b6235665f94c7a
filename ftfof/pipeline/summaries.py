"""A stage's full report and, beside it (:func:`ftfof.pipeline.catalog.summary_beside`), the
short summary dvc.yaml lists as its metrics (:mod:`ftfof.report.stage_summaries`)."""

from __future__ import annotations

from pathlib import Path

from ftfof.files import write_json
from ftfof.pipeline import catalog
from ftfof.report.stage_summaries import SUMMARIES, Report


def write_metrics(stage: str, path: Path, report: Report) -> None:
    """The stage's full report at ``path`` and its summary beside it."""
    write_json(path, report)
    write_json(catalog.summary_beside(path, stage), SUMMARIES[stage](report))
