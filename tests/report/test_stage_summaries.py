"""The stages' DVC summaries from in-memory reports: short, and what each reads."""

from __future__ import annotations

from ftfof.report import stage_summaries as summaries
from ftfof.surrogate.store import TARGETS


def test_the_widest_train_summary_stays_short():
    """Both losses and a peak GP for every target: still within the limit."""
    entry = {"best_epoch": 3, "seconds": 1.0, "targets": {t: {"mse": 1.0} for t in TARGETS}}
    peaks = {t: {"gp": {"spearman": 0.5}, "gru": {"spearman": 0.4}} for t in TARGETS}
    report = {"wall_seconds": 2.0, "dilate": entry, "mse": entry, "peaks": peaks}
    assert summaries.numbers(summaries.train(report)) <= summaries.LIMIT


def test_refine_summarises_the_last_round_on_the_first_objective():
    fidelity = {"spearman": 0.9, "median_relative_error": 0.05, "mean": 1.0}
    last = {
        "added": 4,
        "fidelity": {"fs1": fidelity, "fs7": fidelity},
        "optimum": {"predicted": {"fs1": 6.0}, "simulated": {"fs1": 6.5}},
    }
    report = {"rounds": [{**last, "added": 3}, last], "seconds": 2.0}
    assert summaries.refine(report) == {
        "rounds": 2,
        "added": 7,
        "seconds": 2.0,
        "last": {
            "objective": "fs1",
            "spearman": 0.9,
            "median_relative_error": 0.05,
            "predicted": 6.0,
            "simulated": 6.5,
        },
    }
    assert summaries.refine({"rounds": []}) == {"rounds": 0, "added": 0}


def test_numbers_counts_numeric_leaves_only():
    assert summaries.numbers({"a": 1, "b": [2.0, True, "x"], "c": {"d": None, "e": 3}}) == 3


def test_evaluate_keeps_the_optimum_figures_and_its_climb():
    row = {"peak_pull": 6.0, "peak_pull_change": -10.0, "other": 1.0}
    report = {
        "reference": "polynomial",
        "table": {"optimum": row},
        "climb": {"optimum": {"jitter": 1.0, "steps_done": 8, "fell": False, "x": 2}},
        "seconds": 3.0,
    }
    assert summaries.evaluate(report) == {
        "reference": "polynomial",
        "optimum": {
            "peak_pull": 6.0,
            "peak_pull_change": -10.0,
            "climb": {"jitter": 1.0, "steps_done": 8, "fell": False},
        },
        "seconds": 3.0,
    }
