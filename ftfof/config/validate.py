"""A settings document (``params.yaml`` as parsed YAML) validated into :class:`Params`: every
problem one line naming its key path."""

from __future__ import annotations

from pydantic import ValidationError
from pydantic_core import ErrorDetails

from ftfof.config import LEG_TYPES, Params
from ftfof.errors import ParamsError


def format_validation_error(err: ValidationError) -> str:
    """Every problem as 'key.path: pydantic's message (got value)', one per line."""
    lines = [_problem(e) for e in err.errors(include_url=False)]
    if len(lines) == 1:
        return lines[0]
    return f"{len(lines)} problems:\n" + "\n".join(f"  {line}" for line in lines)


def _problem(error: ErrorDetails) -> str:
    # A discriminated union puts its tag in the location (robots.x.leg.planar3.hip): not a key.
    path = ".".join(str(p) for p in error["loc"] if p not in LEG_TYPES)
    what = error["msg"].removeprefix("Value error, ")
    if not isinstance(error["input"], dict):  # a whole block (missing key, model check): not shown
        what += f" (got {error['input']!r})"
    return f"{path}: {what}" if path else what


def parse_params(raw: object, source: str = "params.yaml") -> Params:
    """Validate an already-parsed YAML document."""
    if not isinstance(raw, dict):
        raise ParamsError(source, "must be a YAML mapping of sections")
    try:
        return Params.model_validate(raw)
    except ValidationError as err:
        raise ParamsError(source, format_validation_error(err)) from None
