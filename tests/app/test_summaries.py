"""Each stage's DVC summary: at most LIMIT numbers, the only file dvc.yaml lists as its metrics,
and what `ftfof sweep` reads is in evaluate's."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from ftfof.pipeline import catalog, summaries
from ftfof.pipeline.sweep import SUMMARY
from ftfof.report import stage_summaries
from ftfof.study.sweep import KEY_METRICS

ROOT = Path(__file__).resolve().parents[2]
STAGES = yaml.safe_load((ROOT / "dvc.yaml").read_text())["stages"]
FULL = {  # stage -> its full report in the catalog
    "sample": "sample_metrics",
    "acquire": "acquire_metrics",
    "dataset": "dataset_metrics",
    "train": "train_metrics",
    "optimize": "optimize_metrics",
    "refine": "refine_report",
    "polish": "polish_report",
    "climb": "climb_table",
    "slip": "slip_table",
    "study": "eps_study",
    "evaluate": "metrics",
    "identify": "identify",
}


def _report(stage: str) -> dict:
    return json.loads((ROOT / catalog.path(FULL[stage])).read_text())


def test_every_stage_has_a_summariser():
    assert set(stage_summaries.SUMMARIES) == set(STAGES) == set(FULL)


@pytest.mark.parametrize("stage", sorted(FULL))
def test_dvc_lists_the_summary_as_the_metrics_and_the_full_report_as_an_output(stage):
    spec = STAGES[stage]
    metrics = [next(iter(m)) if isinstance(m, dict) else m for m in spec["metrics"]]
    assert metrics == [catalog.path(f"{stage}_summary").as_posix()]
    outs = {next(iter(o)) if isinstance(o, dict) else o for o in spec["outs"]}
    assert catalog.path(FULL[stage]).as_posix() in outs
    assert catalog.summary_beside(catalog.path(FULL[stage]), stage) == catalog.path(
        f"{stage}_summary"
    )


@pytest.mark.parametrize("stage", sorted(FULL))
def test_the_committed_reports_summaries_are_short_and_committed(stage):
    summary = stage_summaries.SUMMARIES[stage](_report(stage))
    assert 3 <= stage_summaries.numbers(summary) <= stage_summaries.LIMIT
    committed = ROOT / catalog.path(f"{stage}_summary")
    assert json.loads(committed.read_text()) == json.loads(json.dumps(summary))


def test_evaluate_summary_holds_what_sweep_prints():
    assert catalog.path("evaluate_summary").as_posix() == SUMMARY
    summary = stage_summaries.evaluate(_report("evaluate"))
    assert summary["reference"]
    for metric in KEY_METRICS:
        assert {metric, f"{metric}_change"} <= set(summary["optimum"])


def test_write_metrics_puts_the_summary_beside_the_report(tmp_path):
    report = {"rounds": [], "seconds": 1.5}
    summaries.write_metrics("refine", tmp_path / "refine.json", report)
    assert json.loads((tmp_path / "refine.json").read_text()) == report
    written = json.loads((tmp_path / "summary" / "refine.json").read_text())
    assert written == {"rounds": 0, "added": 0, "seconds": 1.5}
