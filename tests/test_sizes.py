"""The rooms stay small (the brief's style rules, issue 52's acceptance): no module over 400
lines, no class over 150, no function over 60 (def line to last line) across ftfof/ and
stages/, and every stage command at most 50."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from ftfof.pipeline.imports import ROOT

SOURCES = sorted([*(ROOT / "ftfof").rglob("*.py"), *(ROOT / "stages").glob("*.py")])
LIMITS = {ast.ClassDef: 150, ast.FunctionDef: 60, ast.AsyncFunctionDef: 60}


def lines(node: ast.AST) -> int:
    return node.end_lineno - node.lineno + 1  # type: ignore[attr-defined]


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_a_module_and_its_classes_and_functions_keep_their_sizes(path: Path):
    text = path.read_text()
    assert len(text.splitlines()) <= 400, f"{path.name}: a module over 400 lines"
    for node in ast.walk(ast.parse(text)):
        limit = LIMITS.get(type(node))
        if limit is not None:
            assert lines(node) <= limit, f"{path.name}: {node.name} is {lines(node)} lines"


def test_every_stage_command_is_at_most_fifty_lines():
    for path in sorted((ROOT / "stages").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.FunctionDef):
                continue
            if any(getattr(d, "id", "") == "stage" for d in node.decorator_list):
                assert lines(node) <= 50, f"{path.name}: {node.name} is {lines(node)} lines"
