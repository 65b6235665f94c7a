"""`ftfof profile NAME`: overlay profiles/NAME.yaml on params.yaml, keeping its comments.

A profile changes sizes (samples, epochs, generations), not physics; the result is validated
before params.yaml is replaced, so a bad profile leaves the file as it was.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ftfof.pipeline import catalog
from stages.common import ParamsOption, console, stage

PROFILES = catalog.PROFILES


@stage
def command(
    name: Annotated[str, typer.Argument(help="A profile under profiles/ (e.g. tiny).")],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    profiles: Annotated[Path, typer.Option(help="Directory of profiles.")] = PROFILES,
) -> None:
    """Apply a named profile of overrides to params.yaml (validated, comments kept)."""
    from ftfof.errors import ParamsError
    from ftfof.pipeline.params_file import edit_params, read_yaml

    source = profiles / f"{name}.yaml"
    if not source.exists():
        have = sorted(p.stem for p in profiles.glob("*.yaml"))
        raise ParamsError(str(source), f"no such profile (have {', '.join(have) or 'none'})")
    overlay = read_yaml(source) or {}
    changed = edit_params(params_path, lambda document: _merge(document, overlay, ""))
    console.print(f"profile {name}: {', '.join(changed)} -> {params_path}")


def _merge(target: Any, overlay: dict, prefix: str) -> list[str]:
    """Set every leaf of ``overlay`` in ``target`` (in place); the dotted keys changed."""
    from ftfof.errors import ParamsError

    changed = []
    for key, value in overlay.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict):
            if not isinstance(target.get(key), dict):
                raise ParamsError(path, "the profile names a section params.yaml does not have")
            changed += _merge(target[key], value, f"{path}.")
        else:
            target[key] = value
            changed.append(f"{path}={value}")
    return changed
