"""`ftfof profile NAME`: overlay profiles/NAME.yaml on params.yaml, keeping its comments;
`ftfof profile --undo` puts back the file as it was before the first profile.

A profile changes sizes (samples, epochs, generations), not physics; the result is validated
before params.yaml is replaced, so a bad profile leaves the file as it was. The file before the
first profile is kept beside it (``params.yaml.before-profile``) until it is undone.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ftfof.pipeline import catalog
from stages.common import ParamsOption, console, stage

PROFILES = catalog.PROFILES


BACKUP = ".before-profile"  # suffix of the params file as it was before the first profile


@stage
def command(
    name: Annotated[
        str | None, typer.Argument(help="A profile under profiles/ (e.g. tiny).")
    ] = None,
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    profiles: Annotated[Path, typer.Option(help="Directory of profiles.")] = PROFILES,
    undo: Annotated[
        bool, typer.Option("--undo", help="Put back params.yaml as before the first profile.")
    ] = False,
) -> None:
    """Apply a named profile of overrides to params.yaml (validated, comments kept), or undo."""
    from ftfof.errors import ParamsError
    from ftfof.files import atomic_path
    from ftfof.pipeline.params_file import edit_params, read_yaml

    backup = params_path.with_name(params_path.name + BACKUP)
    if undo == (name is not None):
        raise ParamsError("profile", "give a profile name, or --undo alone")
    if undo:
        if not backup.exists():
            raise ParamsError(str(backup), "no profile to undo (no saved params file)")
        backup.replace(params_path)
        console.print(f"profile undone: {params_path} is as before the first profile")
        return
    source = profiles / f"{name}.yaml"
    if not source.exists():
        have = sorted(p.stem for p in profiles.glob("*.yaml"))
        raise ParamsError(str(source), f"no such profile (have {', '.join(have) or 'none'})")
    overlay = read_yaml(source) or {}
    original = params_path.read_bytes() if params_path.exists() else None
    changed = edit_params(params_path, lambda document: _merge(document, overlay, ""))
    if original is not None and not backup.exists():
        with atomic_path(backup) as tmp:
            tmp.write_bytes(original)
    console.print(
        f"profile {name}: {', '.join(changed)} -> {params_path} "
        f"(`ftfof profile --undo` puts back the file of {backup.name})"
    )


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
