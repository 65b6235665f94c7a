"""Table I analogue: % changes against a reference, checked on the paper's own table."""

import pytest

from ftfof.evaluate.table import PAPER_TABLE_I, table_one


def test_paper_table_gives_the_published_reductions():
    rows = {r.trajectory: r for r in table_one(PAPER_TABLE_I, "polynomial")}
    # FTFOF §VI.D: detachment force -28 %, body jitter -82 % against the polynomial
    assert round(rows["optimal"].change["peak_detachment"]) == -28
    assert round(rows["optimal"].change["peak_body_acc"]) == -82
    assert rows["polynomial"].change == {k: 0.0 for k in rows["polynomial"].change}
    assert list(rows) == list(PAPER_TABLE_I)


def test_missing_or_zero_reference_is_named():
    with pytest.raises(ValueError, match="cycloid"):
        table_one(PAPER_TABLE_I, "cycloid")
    broken = {"polynomial": {**PAPER_TABLE_I["polynomial"], "peak_body_acc": 0.0}}
    with pytest.raises(ValueError, match="max body jitter"):
        table_one(broken, "polynomial")


def test_the_climb_record_rounds_figures_and_names_what_was_not_climbed():
    from ftfof.evaluate.table import climb_record

    climbs = {"optimum": {"summary": {"jitter": 1.234567, "fell": False, "steps": 8}, "fall": None,
                          "error": None}}  # fmt: skip
    record = climb_record(climbs, {"polynomial": "rule a; rule b"})
    assert record["optimum"] == {"jitter": 1.2346, "fell": False, "steps": 8, "fall": None,
                                 "error": None}  # fmt: skip
    assert record["not_climbed"] == {"polynomial": "rule a; rule b"}
    assert "not_climbed" not in climb_record(climbs, {})
