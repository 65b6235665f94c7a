"""`ftfof profile NAME`: overlay profiles/NAME.yaml on params.yaml, keeping its comments.

A profile changes sizes (samples, epochs, generations), not physics; the result is validated
before params.yaml is replaced, so a bad profile leaves the file as it was.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Annotated, Any

import typer

from stages.common import ParamsOption, atomic_path, console, stage

PROFILES = Path("profiles")


@stage
def command(
    name: Annotated[str, typer.Argument(help="A profile under profiles/ (e.g. tiny).")],
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    profiles: Annotated[Path, typer.Option(help="Directory of profiles.")] = PROFILES,
) -> None:
    """Apply a named profile of overrides to params.yaml (validated, comments kept)."""
    from ruamel.yaml import YAML, YAMLError

    from ftfof.errors import ParamsError
    from stages.params import parse_params

    source = profiles / f"{name}.yaml"
    if not source.exists():
        have = sorted(p.stem for p in profiles.glob("*.yaml"))
        raise ParamsError(str(source), f"no such profile (have {', '.join(have) or 'none'})")
    yaml = YAML()
    yaml.preserve_quotes = True
    yaml.width = 4096  # never re-wrap the user's lines
    yaml.representer.add_representer(
        type(None), lambda r, _: r.represent_scalar("tag:yaml.org,2002:null", "null")
    )
    try:
        overlay = yaml.load(source.read_text())
        document = yaml.load(params_path.read_text())
    except YAMLError as err:
        raise ParamsError(str(source), f"not valid YAML ({str(err).splitlines()[0]})") from None
    _keep_anchors(document)
    changed = _merge(document, overlay or {}, "")
    parse_params(_plain(document), str(params_path))
    buffer = io.StringIO()
    yaml.dump(document, buffer)
    with atomic_path(params_path) as tmp:
        tmp.write_text(buffer.getvalue())
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


def _plain(node: Any) -> Any:
    if isinstance(node, dict):
        return {str(k): _plain(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_plain(v) for v in node]
    return node
