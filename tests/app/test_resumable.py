"""Resumable outputs: an interrupted run resumes only under the same fingerprint and source."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ftfof.digests import tree_sha256
from ftfof.pipeline import jobs


def test_tree_digest_names_files_by_relative_path_and_bytes(tmp_path: Path):
    for root in ("a", "b"):
        for sub in ("x", "y"):
            (tmp_path / root / sub).mkdir(parents=True)
            (tmp_path / root / sub / "m.py").write_text(f"{sub} = 1\n")
        (tmp_path / root / "notes.txt").write_text(root)
    a, b = tmp_path / "a", tmp_path / "b"
    assert tree_sha256(a, "*.py") == tree_sha256(b, "*.py")  # same tree elsewhere, other .txt
    (b / "x" / "m.py").rename(b / "x" / "n.py")
    assert tree_sha256(a, "*.py") != tree_sha256(b, "*.py")


@pytest.mark.parametrize("edited", [False, True])
def test_an_interrupted_run_resumes_only_under_the_code_that_began_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, edited: bool
):
    out = tmp_path / "polish"
    key = jobs.open_resumable(out, {"seed": 1})
    (out / "journal.jsonl").write_text('{"generation": 0}\n')  # killed mid-run
    if edited:
        monkeypatch.setattr(jobs, "source", lambda: "another source")
    assert jobs.open_resumable(out, {"seed": 1}) == key
    assert (out / "journal.jsonl").exists() is not edited
    jobs.close_resumable(out, key)
    assert json.loads((out / "manifest.json").read_text()) == {"fingerprint": key, "complete": True}
    assert jobs.open_resumable(out, {"seed": 1}) == key  # a finished run starts afresh
    assert not (out / "journal.jsonl").exists()
