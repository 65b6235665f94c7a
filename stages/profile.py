"""`ftfof profile NAME`: overlay profiles/NAME.yaml on params.yaml, keeping its comments.

A profile changes sizes (samples, epochs, generations), not physics; the result is validated
before params.yaml is replaced, so a bad profile leaves the file as it was.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Annotated, Any

import typer

from ftfof.pipeline.io import atomic_path
from stages.common import ParamsOption, console, stage

PROFILES = Path("profiles")


@stage
def command(
    name: Annotated[str, typer.Argument(help="A profile under profiles/ (e.g. tiny).")],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    profiles: Annotated[Path, typer.Option(help="Directory of profiles.")] = PROFILES,
) -> None:
    """Apply a named profile of overrides to params.yaml (validated, comments kept)."""
    import yaml as pyyaml
    from ruamel.yaml import YAML

    from ftfof.errors import ParamsError
    from stages.params import parse_params

    source = profiles / f"{name}.yaml"
    if not source.exists():
        have = sorted(p.stem for p in profiles.glob("*.yaml"))
        raise ParamsError(str(source), f"no such profile (have {', '.join(have) or 'none'})")
    # Round trip ("rt") keeps params.yaml's comments and layout; like "safe" it builds only
    # plain YAML types, never Python objects named by tags. The overlay needs no layout.
    round_trip = YAML(typ="rt")
    round_trip.preserve_quotes = True
    round_trip.width = 4096  # never re-wrap the user's lines
    round_trip.representer.add_representer(
        type(None), lambda r, _: r.represent_scalar("tag:yaml.org,2002:null", "null")
    )
    overlay = _parse(YAML(typ="safe"), source)
    document = _parse(round_trip, params_path)
    _keep_anchors(document)
    changed = _merge(document, overlay or {}, "")
    buffer = io.StringIO()
    round_trip.dump(document, buffer)
    text = buffer.getvalue()
    parse_params(pyyaml.safe_load(text), str(params_path))  # exactly what will be written
    with atomic_path(params_path) as tmp:
        tmp.write_text(text)
    console.print(f"profile {name}: {', '.join(changed)} -> {params_path}")


def _parse(loader: Any, path: Path) -> Any:
    from ruamel.yaml import YAMLError

    from ftfof.errors import ParamsError

    try:
        return loader.load(path.read_text())
    except YAMLError as err:
        raise ParamsError(str(path), f"not valid YAML ({str(err).splitlines()[0]})") from None


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
