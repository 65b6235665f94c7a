"""The project's imports read from its source (nothing is imported): which project modules a
file names, and which files importing a module loads. `ftfof dvc-yaml` takes each stage's code
dependencies from it; the layering test reads the same graph."""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the checkout: ftfof/ and stages/ beside
PACKAGES = ("ftfof", "stages")


def module_file(module: str) -> Path | None:
    """The file that defines ``module`` (a package resolves to its ``__init__.py``)."""
    base = ROOT.joinpath(*module.split("."))
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    return None


@cache  # read once a process: dvc.yaml's twelve stages walk the same files
def imported_modules(path: Path) -> frozenset[str]:
    """Every project module ``path`` names in an import, wherever the import stands, but inside a
    module's ``__getattr__`` (PEP 562): an attribute loaded on first use, which importing the
    module does not load (``ftfof.open_run``)."""
    package = ".".join(path.relative_to(ROOT).with_suffix("").parts)
    if path.name != "__init__.py":
        package = package.rpartition(".")[0]
    found: set[str] = set()
    tree = ast.parse(path.read_text(), str(path))
    lazy = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "__getattr__"]
    skipped = {id(node) for function in lazy for node in ast.walk(function)}
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                base = f"{parent}.{base}" if base else parent
            found.add(base)
            found.update(f"{base}.{alias.name}" for alias in node.names)
    return frozenset(m for m in found if m.split(".")[0] in PACKAGES)


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


def command_modules(cli: Path | None = None) -> dict[str, str]:
    """Sub-command name -> the stages module that defines it, read from ``stages/cli.py``: the
    ``app.command("name")(module.command)`` lines, and ``app.add_typer(module.app, name=...)``
    for a command group (its sub-commands live in that module)."""
    out = {}
    for node in ast.walk(ast.parse((cli or ROOT / "stages/cli.py").read_text())):
        if not isinstance(node, ast.Call) or not node.args:
            continue
        target = node.args[0]
        if not (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name)):
            continue
        module = f"stages.{target.value.id}"
        if isinstance(node.func, ast.Call) and getattr(node.func.func, "attr", "") == "command":
            name = node.func.args[0]
        elif isinstance(node.func, ast.Attribute) and node.func.attr == "add_typer":
            name = next(k.value for k in node.keywords if k.arg == "name")
        else:
            continue
        assert isinstance(name, ast.Constant)
        out[name.value] = module
    return out
