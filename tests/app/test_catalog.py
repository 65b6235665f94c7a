"""The artefact catalog against dvc.yaml and the code: one place names every path, and every
format's writer and reader exist."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest
import yaml

from ftfof.pipeline import catalog, dvcfile

ROOT = Path(__file__).resolve().parents[2]
STAGES = yaml.safe_load((ROOT / "dvc.yaml").read_text())["stages"]
CODE = ("ftfof", "stages")


def _paths(entries) -> set[str]:
    return {e if isinstance(e, str) else next(iter(e)) for e in entries or []}


def test_every_dvc_stage_is_in_the_catalog_and_no_other():
    assert set(STAGES) == set(catalog.STAGES)


@pytest.mark.parametrize("stage", sorted(STAGES))
def test_dvc_deps_and_outs_are_the_catalogs(stage: str):
    spec = STAGES[stage]
    reads, writes = catalog.STAGES[stage]
    data_deps = {d for d in spec.get("deps", []) if not d.startswith(CODE)}
    assert data_deps == {catalog.tracked(n).as_posix() for n in reads}
    outs = _paths(spec.get("outs")) | _paths(spec.get("metrics")) | _paths(spec.get("plots"))
    assert outs == {catalog.path(n).as_posix() for n in writes}
    assert all(catalog.ARTEFACTS[n].writer == dvcfile.STAGES[stage].command for n in writes)


def test_every_artefact_a_stage_reads_is_written_by_a_command():
    read = {n for reads, _ in catalog.STAGES.values() for n in reads}
    assert read <= set(catalog.ARTEFACTS)
    written = {n for _, writes in catalog.STAGES.values() for n in writes}
    parts = {n for n, a in catalog.ARTEFACTS.items() if a.part_of in written}
    commands = {s.command for s in dvcfile.STAGES.values()}
    outside = {n for n, a in catalog.ARTEFACTS.items() if a.writer not in commands}
    assert read <= written | parts | outside


@pytest.mark.parametrize("name", sorted(catalog.FORMATS))
def test_each_format_has_one_writer_and_its_reader_and_they_exist(name: str):
    for target in catalog.FORMATS[name]:
        if target is not None:
            module, _, attr = target.partition(":")
            assert callable(getattr(importlib.import_module(module), attr)), target
    assert any(a.format == name for a in catalog.ARTEFACTS.values()), f"{name} is unused"


def test_what_a_stage_reads_has_a_reader():
    read = {n for reads, _ in catalog.STAGES.values() for n in reads}
    for name in read:
        artefact = catalog.ARTEFACTS[name]
        assert catalog.FORMATS[artefact.format][1] is not None, f"nothing reads {name}"


def test_a_part_lives_inside_the_artefact_that_holds_it():
    for artefact in catalog.ARTEFACTS.values():
        if artefact.part_of:
            assert artefact.path.parent == catalog.path(artefact.part_of)


def test_the_stage_commands_spell_no_path_of_their_own():
    """Their defaults come from the catalog: no data/ or reports/ path in the code."""
    for module in sorted((ROOT / "stages").glob("*.py")):
        code = module.read_text()
        for root in ("data/", "reports/"):
            literal = [line for line in code.splitlines() if f'"{root}' in line]
            assert not literal, f"{module.name} spells a path: {literal}"
