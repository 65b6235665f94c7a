"""A refinement round's rows: relabelled as that round's training rows, appended, never clashing."""

import json

import pyarrow as pa
import pytest

from ftfof import config
from ftfof.data import dataset
from ftfof.data.acquisition import to_table
from ftfof.data.refinement import grow, round_rows, source
from ftfof.errors import DataError
from tests.data.fake import fake_acquisition, fake_result


def _built(table: pa.Table) -> pa.Table:
    built, _ = dataset.build(table, config.Dataset(seq_len=16), seed=0)
    return built


def _front(ids) -> pa.Table:
    results = [fake_result(f"front:{i}", "front", i, 2.0 + i) for i in ids]
    return to_table(results, "mst_m3f", "acrylic", {}, 1.0, with_wall_time=False)


def test_rows_name_their_round_and_keep_the_builds_split():
    built = _built(_front(range(1, 21)))
    rows = round_rows(built, 2)
    assert rows.column("source").to_pylist() == [source(2)] * 20
    keys = rows.column("key").to_pylist()
    assert sorted(keys)[:3] == ["refine:2:1", "refine:2:10", "refine:2:11"]
    assert rows.column("split").equals(built.column("split"))
    assert rows.column("split").to_pylist().count("validation") == 3  # 15 % of 20, held out


def test_grow_appends_in_order_and_keeps_the_original_rows_and_metadata():
    original = _built(fake_acquisition(12, failed=0))
    original = original.replace_schema_metadata({b"ftfof": json.dumps({"seq_len": 16})})
    first, second = round_rows(_built(_front([1, 2])), 1), round_rows(_built(_front([1, 4])), 2)
    grown = grow(original, [first, second])
    assert grown.num_rows == original.num_rows + 4
    assert grown.slice(0, original.num_rows).column("key").equals(original.column("key"))
    assert grown.column("source").to_pylist()[-4:] == ["refine:1"] * 2 + ["refine:2"] * 2
    assert grown.schema.metadata == original.schema.metadata
    assert grow(original, []) is original


def test_a_key_twice_is_refused():
    original = _built(fake_acquisition(12, failed=0))
    rows = round_rows(_built(_front([1, 2])), 1)
    with pytest.raises(DataError, match="already in the dataset"):
        grow(original, [rows, rows])
