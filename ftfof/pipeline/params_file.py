"""Load ``params.yaml`` once, at the edge, validated (:mod:`ftfof.config.validate`: errors that
name the key path); and rewrite it, the one way every command that edits it uses."""

from __future__ import annotations

import io
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import yaml

from ftfof.config import Params
from ftfof.config.validate import parse_params
from ftfof.errors import ParamsError
from ftfof.files import atomic_path

T = TypeVar("T")


def load_params(path: Path) -> Params:
    """Read, parse and validate ``path``; every failure is a one-line :class:`ParamsError`."""
    return parse_params(read_yaml(path), str(path))


def read_yaml(path: Path) -> Any:
    """The plain data of a YAML file; an unreadable or malformed file is a :class:`ParamsError`."""
    return _parsed(yaml.safe_load, _read(path), path)


def edit_params(path: Path, edit: Callable[[Any], T]) -> T:
    """The one way params.yaml is rewritten: ``edit`` changes its round-trip document in place,
    and the file is replaced, comments and anchors kept, only if the result validates."""
    text, result = edit_yaml(_read(path), edit, path)
    parse_params(yaml.safe_load(text), str(path))  # exactly what will be written
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return result


def edit_yaml(text: str, edit: Callable[[Any], T], source: Path) -> tuple[str, T]:
    """``text`` after ``edit`` on its ruamel round-trip document, and what ``edit`` returned."""
    from ruamel.yaml import YAML

    # Round trip ("rt") keeps comments and layout; like "safe" it builds only plain YAML types,
    # never Python objects named by tags.
    round_trip = YAML(typ="rt")
    round_trip.preserve_quotes = True
    round_trip.width = 4096  # never re-wrap the user's lines
    round_trip.representer.add_representer(type(None), _null)
    round_trip.representer.add_representer(float, _float)
    document = _parsed(round_trip.load, text, source)
    _keep_anchors(document)
    result = edit(document)
    buffer = io.StringIO()
    round_trip.dump(document, buffer)
    return buffer.getvalue(), result


def yaml_float(value: float) -> str:
    """``repr`` with a point in the mantissa: PyYAML (YAML 1.1) reads ``1e-05`` as a string."""
    text = repr(value)
    if "e" in text and "." not in text:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}.0e{exponent}"
    return text


def _float(representer: Any, value: float) -> Any:
    if not math.isfinite(value):
        return representer.represent_float(value)
    return representer.represent_scalar("tag:yaml.org,2002:float", yaml_float(value))


def _null(representer: Any, _: None) -> Any:
    return representer.represent_scalar("tag:yaml.org,2002:null", "null")


def _read(path: Path) -> str:
    try:
        return path.read_text()
    except OSError as err:
        raise ParamsError(str(path), f"cannot read ({err.strerror})") from None


def _parsed(load: Callable[[str], Any], text: str, source: Path) -> Any:
    """``load(text)``; PyYAML's and ruamel's errors alike become one line naming the line."""
    from ruamel.yaml import YAMLError as RuamelError

    try:
        return load(text)
    except (yaml.YAMLError, RuamelError) as err:
        mark = getattr(err, "problem_mark", None)
        where = f"{source}:{mark.line + 1}" if mark else str(source)
        raise ParamsError(where, f"not valid YAML ({getattr(err, 'problem', err)})") from None


def _keep_anchors(node: Any) -> None:
    """ruamel drops anchors nothing refers to yet; params.yaml keeps them for new presets."""
    anchor = getattr(node, "anchor", None)
    if anchor is not None and anchor.value:
        anchor.always_dump = True
    if isinstance(node, dict):
        for value in node.values():
            _keep_anchors(value)
    elif isinstance(node, list):
        for value in node:
            _keep_anchors(value)
