"""Load and validate ``params.yaml`` once, at the edge, with errors that name the key path."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml
from pydantic import ValidationError

from ftfof.config import Params
from ftfof.errors import ParamsError

_MESSAGES = {
    "greater_than": "must be > {gt}",
    "greater_than_equal": "must be >= {ge}",
    "less_than_equal": "must be <= {le}",
    "less_than": "must be < {lt}",
    "extra_forbidden": "unknown key",
    "missing": "required key is missing",
    "float_parsing": "must be a number",
    "float_type": "must be a number",
    "int_parsing": "must be an integer",
    "int_type": "must be an integer",
    "int_from_float": "must be an integer",
    "bool_parsing": "must be true or false",
    "string_type": "must be a string",
    "literal_error": "must be one of {expected}",
    "too_short": "needs at least {min_length} items",
    "tuple_type": "must be a list",
    "list_type": "must be a list",
    "dict_type": "must be a mapping",
    "model_type": "must be a mapping",
    "union_tag_invalid": "unknown type {tag!r} (expected one of {expected_tags})",
    "union_tag_not_found": "needs a 'type' key",
}


def _path(loc: tuple[Any, ...], error_type: str) -> str:
    parts = [str(p) for p in loc]
    # Discriminated unions put the tag in the location (robots.x.leg.planar3.hip): drop it.
    parts = [p for p in parts if p not in ("planar3", "spatial3")]
    return ".".join(parts) or "params"


def format_validation_error(err: ValidationError) -> str:
    """Every problem as 'key.path: what is wrong (got value)', one per line."""
    lines = [_problem(e) for e in err.errors()]
    if len(lines) == 1:
        return lines[0]
    return f"{len(lines)} problems:\n" + "\n".join(f"  {line}" for line in lines)


def _problem(error: Any) -> str:
    template = _MESSAGES.get(error["type"])
    ctx = {k: f"{v:g}" if isinstance(v, float) else v for k, v in error.get("ctx", {}).items()}
    if template is not None:
        what = template.format(**ctx)
    else:
        what = error["msg"].removeprefix("Value error, ")
    if error["type"] not in ("missing", "extra_forbidden", "union_tag_not_found"):
        what += f" (got {error['input']!r})" if not isinstance(error["input"], dict) else ""
    return f"{_path(error['loc'], error['type'])}: {what}"


def parse_params(raw: object, source: str = "params.yaml") -> Params:
    """Validate an already-parsed YAML document."""
    if not isinstance(raw, dict):
        raise ParamsError(source, "must be a YAML mapping of sections")
    try:
        return Params.model_validate(raw)
    except ValidationError as err:
        raise ParamsError(source, format_validation_error(err)) from None


def load_params(path: Path) -> Params:
    """Read, parse and validate ``path``; every failure is a one-line :class:`ParamsError`."""
    try:
        text = path.read_text()
    except OSError as err:
        raise ParamsError(str(path), f"cannot read ({err.strerror})") from None
    try:
        raw = yaml.safe_load(text)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark else str(path)
        raise ParamsError(where, f"not valid YAML ({getattr(err, 'problem', err)})") from None
    return parse_params(raw, str(path))
