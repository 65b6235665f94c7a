"""The import structure: each layer imports only the layers below it, and no modules import each
other in a loop. A new package gets a rank here, or this test names it."""

from __future__ import annotations

from pathlib import Path

import pytest

from ftfof.pipeline.imports import ROOT, imported_modules

# the unit of a rank: a subpackage of ftfof, a top-level ftfof module, or stages
RANKS = {
    "ftfof.errors": 0,
    "ftfof.seeds": 0,
    "ftfof.stats": 0,
    "ftfof.config": 0,
    "ftfof.version": 0,
    "ftfof.digests": 1,
    "ftfof.objectives": 1,
    "ftfof.demand": 1,
    "ftfof.kinematics": 1,
    "ftfof.identify": 1,
    "ftfof.trajectory": 2,
    "ftfof.sim": 3,
    "ftfof.rules": 4,
    "ftfof.data": 5,
    "ftfof.robot": 5,
    "ftfof.files": 6,
    "ftfof.climb": 6,
    "ftfof.surrogate": 7,
    "ftfof.optimize": 8,
    "ftfof.evaluate": 9,
    "ftfof.study": 9,
    "ftfof.refine": 10,
    "ftfof.report": 10,
    "ftfof.pipeline": 11,
    "stages": 12,
    "ftfof.__main__": 13,
}


def unit(module: str) -> str:
    parts = module.split(".")
    return parts[0] if parts[0] == "stages" else ".".join(parts[:2])


def modules() -> dict[str, Path]:
    out = {}
    for package in ("ftfof", "stages"):
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out[name] = path
    return out


MODULES = modules()


def imports(name: str) -> set[str]:
    """Project modules ``name`` imports, wherever the import stands (type-checking ones too)."""
    return imported_modules(MODULES[name]) & set(MODULES)


def test_every_module_has_a_layer():
    assert ftfof_units() <= set(RANKS), sorted(ftfof_units() - set(RANKS))


def ftfof_units() -> set[str]:
    return {unit(m) for m in MODULES if m != "ftfof"}


@pytest.mark.parametrize("name", sorted(m for m in MODULES if m != "ftfof"))
def test_no_import_runs_up_a_layer(name: str):
    rank = RANKS[unit(name)]
    up = [m for m in imports(name) if m != "ftfof" and RANKS[unit(m)] > rank]
    assert not up, f"{name} (layer {rank}) imports a higher layer: {up}"


def test_no_modules_import_each_other_in_a_loop():
    graph = {name: imports(name) for name in MODULES}
    state: dict[str, int] = {}  # 1 on the path, 2 done

    def visit(name: str, path: list[str]) -> None:
        state[name] = 1
        for other in sorted(graph[name]):
            if state.get(other) == 1:
                loop = [*path[path.index(other) :], other]
                raise AssertionError(f"import loop: {' -> '.join(loop)}")
            if other not in state:
                visit(other, [*path, other])
        state[name] = 2

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])


RUN_MODULES = {
    f"ftfof.pipeline.{name}"
    for name in ("dataset", "training", "optimize", "refine", "polish", "evaluate", "calibration")
}


@pytest.mark.parametrize("name", sorted(RUN_MODULES))
def test_a_stage_run_imports_no_other_stage_run(name: str):
    """What two stages share is a library call or a shared pipeline module, never a stage's run."""
    assert not (imports(name) & (RUN_MODULES - {name}))
