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
from stages.common import ParamsOption, atomic_path, console, stage, write_json

REPORT = Path("reports/calibration.json")
THIRD_BOUNDS = {
    "preload_pressure": (2e2, 5e4),
    "rate_exponent": (0.1, 1.2),
    "rate_speed": (1e-3, 1.0),
    "shear_ratio": (0.1, 2.0),
    "friction": (0.1, 1.5),
    "contact_stiffness": (1e7, 1e10),
}
BOUNDS = {"strength": (2e3, 5e5), "fracture_energy": (1.0, 5e3)}
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

    from ftfof.sim.calibrate import TABLE_I, calibrate
    from ftfof.sim.spec import Bench
    from ftfof.trajectory.baselines import common_trajectories
    from stages.params import load_params, parse_params
    from stages.robot import robot_context

    params = load_params(params_path)
    ctx = robot_context(params)
    bounds = dict(BOUNDS)
    if third and third != "none":
        if third not in THIRD_BOUNDS:
            raise ParamsError(
                "--third", f"cannot fit {third!r} (choose from {', '.join(THIRD_BOUNDS)})"
            )
        bounds[third] = THIRD_BOUNDS[third]
    trajectories = common_trajectories(ctx.policy, params.baselines, params.base.seed)

    def specs_for(surface):
        bench = Bench(ctx.robot, surface, params.platform, params.acquire, params.base.seed)
        return [bench.analytic(f"baseline:{n}", 0, trajectories[n]) for n in TABLE_I]

    console.print(
        f"calibrating surface {params.surface!r} on {ctx.name}: fitting {', '.join(bounds)}"
    )
    fit = calibrate(params.selected_surface, specs_for, bounds, params.acquire.workers, evaluations)
    write_json(
        report,
        {
            "surface": params.surface,
            "robot": ctx.name,
            "targets": TABLE_I,
            "values": fit.values,
            "residuals": fit.residuals,
            "measured": fit.measured,
            "worst_relative_error": fit.worst,
            "evaluations": fit.evaluations,
            "history": fit.history,
            "baselines": params.baselines.model_dump(),
        },
    )
    for name, value in fit.values.items():
        console.print(f"  {name:18s} {value:.6g}")
    for name, err in fit.residuals.items():
        console.print(f"  {name:34s} {err:+.1%}")
    if write_params:
        text = update_surface(params_path.read_text(), params.surface, fit.values)
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
