"""Each DVC stage's ``deps`` cover every project file its command imports.

The command ``python -m ftfof <name>`` runs ``stages/<module>.py`` as registered in stages/cli.py
(:func:`ftfof.pipeline.imports.command_modules`);
from there the project-internal imports (``ftfof.*``, ``stages.*``, also inside functions) are
followed statically. A dep covers a file when it is that file or a directory above it.
"""

from __future__ import annotations

import pytest
import yaml

from ftfof.pipeline.imports import ROOT, command_modules, imported_files


def covered(path: str, deps: list[str]) -> bool:
    return any(path == d or path.startswith(d.rstrip("/") + "/") for d in deps)


STAGES = yaml.safe_load((ROOT / "dvc.yaml").read_text())["stages"]


@pytest.mark.parametrize("stage", sorted(STAGES))
def test_stage_deps_cover_every_imported_project_file(stage: str):
    spec = STAGES[stage]
    prefix = "python -m ftfof "
    assert spec["cmd"].startswith(prefix), f"{stage}: unexpected command {spec['cmd']!r}"
    module = command_modules()[spec["cmd"].removeprefix(prefix).split()[0]]
    files = {p.relative_to(ROOT).as_posix() for p in imported_files(module)}
    missing = sorted(f for f in files if not covered(f, spec.get("deps", [])))
    assert not missing, f"dvc.yaml stage {stage!r} imports files its deps miss: {missing}"
