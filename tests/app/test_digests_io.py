"""The pipeline's digests and all-or-nothing writes, called directly on small files."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pyarrow as pa
import pytest

from ftfof.digests import (
    bytes_sha256,
    file_sha256,
    files_sha256,
    json_sha256,
    models_digest,
)
from ftfof.errors import DataError
from ftfof.files import atomic_dir, atomic_path, read_table, write_json
from ftfof.pipeline.artefacts import optimum_digest


def test_digests_are_sha256_hex_cut_to_length(tmp_path: Path):
    data = b"ftfof"
    full = hashlib.sha256(data).hexdigest()
    path = tmp_path / "optimum.json"
    path.write_bytes(data)
    assert bytes_sha256(data) == file_sha256(path) == full
    assert file_sha256(path, 16) == optimum_digest(tmp_path) == full[:16]
    text = json.dumps({"a": 1, "b": 2}, sort_keys=True).encode()
    assert json_sha256({"b": 2, "a": 1}, 16) == hashlib.sha256(text).hexdigest()[:16]


def test_models_digest_names_the_directory_by_file_names_and_bytes(tmp_path: Path):
    (tmp_path / "a.pt").write_bytes(b"1")
    (tmp_path / "b.json").write_bytes(b"2")
    before = models_digest(tmp_path)
    assert before == files_sha256([tmp_path / "b.json", tmp_path / "a.pt"])
    (tmp_path / "a.pt").write_bytes(b"3")
    assert models_digest(tmp_path) != before
    with pytest.raises(DataError, match="no trained models"):
        models_digest(tmp_path / "missing")


def test_atomic_writes_leave_nothing_behind_on_failure(tmp_path: Path):
    target = tmp_path / "out.json"
    write_json(target, {"x": 1})
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError
    assert json.loads(target.read_text()) == {"x": 1}
    with pytest.raises(RuntimeError), atomic_dir(tmp_path / "dir") as tmp:
        (tmp / "f").write_text("half")
        raise RuntimeError
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json"]


def test_read_table_names_a_missing_or_unreadable_file(tmp_path: Path):
    schema = pa.schema([("x", pa.int64())])
    with pytest.raises(DataError, match="thing not found"):
        read_table(tmp_path / "none.parquet", schema, "thing")
    bad = tmp_path / "bad.parquet"
    bad.write_text("not parquet")
    with pytest.raises(DataError, match="unreadable thing"):
        read_table(bad, schema, "thing")
