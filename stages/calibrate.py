"""`ftfof calibrate`: fit the selected surface to FTFOF Table I with the two baselines.

Writes reports/calibration.json (fitted values, residuals, measurements, every evaluation). With
``--write-params`` it also rewrites the fitted lines of that surface in params.yaml, each with a
comment naming the fit; everything else in the file is left as it is.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Annotated

import typer

from ftfof.errors import ParamsError
from ftfof.pipeline.calibration import THIRD_BOUNDS
from ftfof.pipeline.io import atomic_path, write_json
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
    import yaml

    from ftfof.pipeline.calibration import fit_surface
    from stages.params import load_params, parse_params

    params = load_params(params_path)
    fit = fit_surface(params, third, evaluations)
    write_json(report, fit)
    for name, value in fit["values"].items():
        console.print(f"  {name:18s} {value:.6g}")
    for name, err in fit["residuals"].items():
        console.print(f"  {name:34s} {err:+.1%}")
    if write_params:
        text = update_surface(params_path.read_text(), params.surface, fit["values"])
        parse_params(yaml.safe_load(text), str(params_path))  # must still validate
        with atomic_path(params_path) as tmp:
            tmp.write_text(text)
        console.print(f"wrote the fit into {params_path}")


def update_surface(text: str, surface: str, values: dict[str, float]) -> str:
    """Replace ``surfaces.<surface>.<name>: ...`` lines, keeping the rest of the file intact."""
    lines = text.splitlines(keepends=True)
    in_surfaces = in_block = False
    seen: set[str] = set()
    for i, line in enumerate(lines):
        if re.match(r"^\S", line):
            in_surfaces = line.startswith("surfaces:")
            in_block = False
            continue
        if in_surfaces and re.match(r"^  \S", line):
            in_block = line.strip().rstrip(":") == surface
            continue
        m = re.match(r"^(    )(\w+):", line) if in_block else None
        if m and m.group(2) in values:
            name = m.group(2)
            newline = "\n" if line.endswith("\n") else ""
            lines[i] = f"{m.group(1)}{name}: {values[name]:.6g}  {COMMENT}{newline}"
            seen.add(name)
    missing = set(values) - seen
    if missing:
        raise ParamsError(
            f"surfaces.{surface}",
            f"no line to rewrite for {sorted(missing)} (add them to params.yaml first)",
        )
    return "".join(lines)
