"""Each DVC stage's ``deps`` cover every project file its command imports.

The command ``python -m ftfof <name>`` runs ``stages/<module>.py`` as registered in stages/cli.py;
from there the project-internal imports (``ftfof.*``, ``stages.*``, also inside functions) are
followed statically. A dep covers a file when it is that file or a directory above it.
"""

from __future__ import annotations

import ast

import pytest
import yaml

from tests.imports import ROOT, imported_files


def commands() -> dict[str, str]:
    """Sub-command name -> the stages module registered for it, read from stages/cli.py."""
    out = {}
    for node in ast.walk(ast.parse((ROOT / "stages/cli.py").read_text())):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Call)
            and isinstance(node.func.func, ast.Attribute)
            and node.func.func.attr == "command"
            and isinstance(node.args[0], ast.Attribute)
            and isinstance(node.args[0].value, ast.Name)
        ):
            name = node.func.args[0]
            assert isinstance(name, ast.Constant)
            out[name.value] = f"stages.{node.args[0].value.id}"
    return out


def covered(path: str, deps: list[str]) -> bool:
    return any(path == d or path.startswith(d.rstrip("/") + "/") for d in deps)


STAGES = yaml.safe_load((ROOT / "dvc.yaml").read_text())["stages"]


@pytest.mark.parametrize("stage", sorted(STAGES))
def test_stage_deps_cover_every_imported_project_file(stage: str):
    spec = STAGES[stage]
    prefix = "python -m ftfof "
    assert spec["cmd"].startswith(prefix), f"{stage}: unexpected command {spec['cmd']!r}"
    module = commands()[spec["cmd"].removeprefix(prefix).split()[0]]
    files = {p.relative_to(ROOT).as_posix() for p in imported_files(module)}
    missing = sorted(f for f in files if not covered(f, spec.get("deps", [])))
    assert not missing, f"dvc.yaml stage {stage!r} imports files its deps miss: {missing}"
