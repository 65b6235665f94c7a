"""The metrics each stage's MLflow run logs: one naming scheme, no NaN."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from ftfof.pipeline import catalog
from ftfof.report import run_metrics

ROOT = Path(__file__).resolve().parents[2]
SCHEME = re.compile(r"^[a-z][a-z0-9_]*(\.[A-Za-z0-9_]+)+$")  # docs/user-guide.md


def test_metric_names_are_scope_dot_name():
    assert run_metrics.metric_name("fidelity", "fs1", "spearman") == "fidelity.fs1.spearman"
    assert run_metrics.metric_name("table", "front 22", "peak_pull") == "table.front_22.peak_pull"
    with pytest.raises(ValueError, match="lowercase"):
        run_metrics.metric_name("Optimum", "fs1")
    with pytest.raises(ValueError, match="no name"):
        run_metrics.metric_name("time")


def test_every_stage_names_its_metrics_by_the_scheme_and_drops_nan():
    """The metrics each stage's run logs, built from the committed paper-scale reports."""

    def report(name):
        return json.loads((ROOT / catalog.path(name)).read_text())

    train = report("train_metrics")
    first_round = report("refine_report")["rounds"][0]
    logged = {
        **run_metrics.train(train),
        **run_metrics.optimize(report("optimize_metrics")),
        **run_metrics.refine_round(first_round),
        **run_metrics.polish(report("polish_report")),
        **run_metrics.evaluate(report("metrics")),
    }
    assert len(logged) > 100
    assert all(SCHEME.match(name) for name in logged), [n for n in logged if not SCHEME.match(n)]
    assert all(math.isfinite(v) for v in logged.values())
    assert {"time.seconds", "optimum.simulated.fs1", "table.optimum.jitter_change"} <= set(logged)
    assert run_metrics.finite({"a.b": float("nan"), "a.c": 1}) == {"a.c": 1.0}


def test_a_models_metrics_are_its_validation_errors_and_best_epoch():
    result = {
        "metrics": {"Fd": {"mae": 0.25, "r2": float("nan")}, "Pf": {"mae": 0.5}},
        "history": {"best_epoch": 17},
    }
    assert run_metrics.train_model(result) == {
        "validation.Fd.mae": 0.25,
        "validation.Pf.mae": 0.5,
        "train.best_epoch": 17.0,
    }


def test_a_polish_that_did_not_polish_logs_its_time_alone():
    assert run_metrics.polish({"polished": False, "seconds": 3.0}) == {"time.seconds": 3.0}


def test_a_runs_settings_are_dotted_strings_beside_the_robot_surface_and_seeds():
    logged = run_metrics.run_settings({"polish": {"a": {"b": 1}, "c": None}}, "r", "glass", 3, 4)
    assert logged == {
        "polish.a.b": "1",
        "polish.c": "None",
        "robot": "r",
        "surface": "glass",
        "base.seed": "3",
        "base.search_seed": "4",
    }


def test_the_evaluate_run_logs_the_fidelity_bound_and_no_climb_notes_as_climbs():
    summary = {
        "table": {"optimum": {"peak_pull": 6.3}},
        "fidelity": {"fs1": {"spearman": 0.9, "n": 20}},
        "fidelity_bound": {"fs1": {"spearman": 0.95, "n": 20}, "held_pull": {"spearman": None}},
        "climb": {
            "optimum": {"fell": True, "steps_done": 3},
            "not_climbed": {"cycloidal": "a rule"},
            "moved_to": {"row": 7, "why": "the optimum fell", "tried": []},
        },
        "seconds": 12.0,
    }
    logged = run_metrics.evaluate(summary)
    assert logged["fidelity.fs1.bound"] == 0.95 and "fidelity.held_pull.bound" not in logged
    assert logged["climb.optimum.fell"] == 1.0
    assert not [name for name in logged if "moved_to" in name or "not_climbed" in name]
