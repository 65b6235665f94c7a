"""`ftfof calibrate`: fit the selected surface to FTFOF Table I with the two baselines.

Writes reports/calibration.json (fitted values, residuals, measurements, every evaluation). With
``--write-params`` it also sets the fitted keys of that surface in params.yaml, each with a comment
naming the fit, through the same round-trip edit as `ftfof profile`: the rest stays as it is.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ftfof.errors import ParamsError
from ftfof.pipeline.calibration import THIRD_BOUNDS
from ftfof.pipeline.io import write_json
from stages.common import ParamsOption, console, stage

REPORT = Path("reports/calibration.json")
COMMENT = "# fitted by ftfof calibrate (reports/calibration.json)"


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    third: Annotated[
        str | None,
        typer.Option(help=f"One more surface parameter to fit: {', '.join(THIRD_BOUNDS)}; 'none'."),
    ] = "preload_pressure",
    evaluations: Annotated[int, typer.Option(min=4, help="Simulation pairs at most.")] = 60,
    report: Annotated[Path, typer.Option(help="Calibration report JSON.")] = REPORT,
    write_params: Annotated[bool, typer.Option(help="Write the fit into params.yaml.")] = False,
) -> None:
    """Fit the surface's strength and fracture energy (and one more) to FTFOF Table I."""
    from ftfof.pipeline.calibration import fit_surface
    from ftfof.pipeline.params_file import edit_params, load_params

    params = load_params(params_path)
    fit = fit_surface(params, third, evaluations)
    write_json(report, fit)
    for name, value in fit["values"].items():
        console.print(f"  {name:18s} {value:.6g}")
    for name, err in fit["residuals"].items():
        console.print(f"  {name:34s} {err:+.1%}")
    if write_params:
        edit_params(
            params_path, lambda document: update_surface(document, params.surface, fit["values"])
        )
        console.print(f"wrote the fit into {params_path}")


def update_surface(document: Any, surface: str, values: dict[str, float]) -> None:
    """Set ``surfaces.<surface>.<name>`` in a round-trip document, each with the fit's comment."""
    from ftfof.pipeline.params_file import yaml_float

    block = document.get("surfaces", {}).get(surface)
    missing = sorted(set(values) - set(block or ()))
    if block is None or missing:
        raise ParamsError(
            f"surfaces.{surface}", f"has no key for {missing} (add them to params.yaml first)"
        )
    for name, value in values.items():
        block[name] = float(f"{value:.6g}")
        # two spaces before the comment, wherever an earlier comment of the key stood
        column = block.lc.col + len(f"{name}: {yaml_float(block[name])}") + 2
        below = _comment_lines_below(block, name)
        block.yaml_add_eol_comment(COMMENT, name, column=column)
        if below:  # ruamel keeps the full-line comments under a key in its end-of-line comment
            block.ca.items[name][2].value += "\n" + below


def _comment_lines_below(block: Any, name: str) -> str:
    """The full-line comments that follow ``name``'s line (kept when its comment is replaced)."""
    token = (block.ca.items.get(name) or [None, None, None])[2]
    if token is None or "\n" not in token.value:
        return ""
    return token.value.split("\n", 1)[1]
