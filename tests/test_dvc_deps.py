"""Each DVC stage's ``deps`` cover every project file its command imports.

The command ``python -m ftfof <name>`` runs ``stages/<module>.py`` as registered in stages/cli.py;
from there the project-internal imports (``ftfof.*``, ``stages.*``, also inside functions) are
followed statically. A dep covers a file when it is that file or a directory above it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("ftfof", "stages")


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


def module_file(module: str) -> Path | None:
    """The file that defines ``module`` (a package resolves to its ``__init__.py``)."""
    base = ROOT.joinpath(*module.split("."))
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    return None


def imported_modules(path: Path) -> set[str]:
    """Every project module ``path`` names in an import, wherever the import stands."""
    package = ".".join(path.relative_to(ROOT).with_suffix("").parts)
    if path.name != "__init__.py":
        package = package.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                base = f"{parent}.{base}" if base else parent
            found.add(base)
            found.update(f"{base}.{alias.name}" for alias in node.names)
    return {m for m in found if m.split(".")[0] in PACKAGES}


def with_parents(module: str) -> list[str]:
    """Importing ``a.b.c`` also runs ``a`` and ``a.b``."""
    parts = module.split(".")
    return [".".join(parts[: i + 1]) for i in range(len(parts))]


def imported_files(module: str) -> set[Path]:
    """Project files loaded by importing ``module``, transitively."""
    seen: set[Path] = set()
    todo = [module]
    while todo:
        for name in with_parents(todo.pop()):
            path = module_file(name)
            if path is not None and path not in seen:
                seen.add(path)
                todo.extend(imported_modules(path))
    return seen


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
