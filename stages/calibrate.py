"""`ftfof calibrate`: fit the selected surface to FTFOF Table I with the two baselines.

Writes reports/calibration.json (fitted and fixed values, the bounds, which bound or cap a value
sits on, residuals, what the fit does to the film, every evaluation). ``--fix key=value`` holds a
value, ``--bound key=lo:hi`` sets a fitted value's range. With ``--write-params`` it also sets
the fitted and fixed keys of that surface in params.yaml, each with a comment naming the fit,
through the same round-trip edit as `ftfof profile`: the rest stays as it is.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ftfof.errors import ParamsError
from ftfof.files import write_json
from ftfof.identify.calibration import FITTABLE, THIRD_BOUNDS
from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, stage

REPORT = path("calibration")
COMMENT = "# fitted by ftfof calibrate (reports/calibration.json)"
HELD = "# held by ftfof calibrate --fix (reports/calibration.json)"


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    third: Annotated[
        str | None,
        typer.Option(help=f"One more surface parameter to fit: {', '.join(THIRD_BOUNDS)}; 'none'."),
    ] = "preload_pressure",
    fix: Annotated[
        list[str] | None,
        typer.Option(help=f"Hold a surface value, key=value (repeatable): {', '.join(FITTABLE)}."),
    ] = None,
    bound: Annotated[
        list[str] | None,
        typer.Option(help="A fitted value's range, key=lo:hi (repeatable)."),
    ] = None,
    evaluations: Annotated[int, typer.Option(min=4, help="Simulation pairs at most.")] = 60,
    report: Annotated[Path, typer.Option(help="Calibration report JSON.")] = REPORT,
    write_params: Annotated[bool, typer.Option(help="Write the fit into params.yaml.")] = False,
) -> None:
    """Fit the surface's strength and fracture energy (one more of its values, and a plate
    foot's backing modulus) to FTFOF Table I."""
    from ftfof.identify.calibration import parse_bounds, parse_fixes
    from ftfof.pipeline.calibration import fit_surface
    from ftfof.pipeline.params_file import edit_params, load_params

    fixed, bounds = parse_fixes(fix or ()), parse_bounds(bound or ())
    params = load_params(params_path)
    fit = fit_surface(params, third, evaluations, fixed, bounds)
    write_json(report, fit)
    show(fit)
    if write_params:
        fixed, values = _split(fit["fixed"]), _split(fit["values"])
        edit_params(
            params_path,
            lambda document: (
                update_surface(document, params.surface, fixed[0], HELD),
                update_surface(document, params.surface, values[0]),
                update_backing(document, params.robot, fixed[1], HELD),
                update_backing(document, params.robot, values[1]),
            ),
        )
        console.print(f"wrote the fit into {params_path}")


def show(fit: dict[str, Any]) -> None:
    """The fit in a few lines: values (and the bound or cap each sits on), residuals, the film."""
    for name, value in fit["fixed"].items():
        on = fit["active"].get(name)
        console.print(f"  {name:18s} {value:.6g}  (fixed{f', {on.upper()}' if on else ''})")
    for name, value in fit["values"].items():
        lo, hi = fit["bounds"][name]
        on = fit["active"].get(name)
        where = f"  ON THE {on.upper()}: Table I does not decide it" if on else ""
        console.print(f"  {name:18s} {value:.6g}  in [{lo:g}, {hi:g}]{where}")
    for name, err in fit["residuals"].items():
        console.print(f"  {name:34s} {err:+.1%}")
    film = fit["film"]
    cap = fit["fracture_energy_cap"]
    console.print(
        f"  critical opening 2G/sigma {1e3 * film['critical_opening']:.2f} mm; peel-root radius "
        f"{1e3 * film['peel_root_radius']:.2f} mm against fc {1e3 * film['fc']:.1f} mm "
        + (
            f"(G cap {cap:.1f} J/m^2: a quasi-static sharp-crack peel's root at fc)"
            if cap is not None
            else "(no cap on G: the plate backs the film)"
        )
    )
    for name, b in film["baselines"].items():
        if b["clamp_edge_radius_if_pulled_at_90deg"] is None:
            console.print(f"  {name}: the run failed, no film measured")
            continue
        console.print(
            f"  {name}: film bent to {1e3 * b['min_bend_radius']:.2f} mm; its "
            f"{b['peak_pull']:.2f} N peak pull would bend the clamp edge to "
            f"{1e3 * b['clamp_edge_radius_if_pulled_at_90deg']:.2f} mm at 90 deg, keeps fc up to "
            f"{b['max_angle_keeping_fc_deg']:.0f} deg"
        )


def _split(values: dict[str, float]) -> tuple[dict[str, float], dict[str, float]]:
    """(the surface's values, the foot backing's values by their key in the backing)."""
    from ftfof.sim.calibrate import FOOT

    return (
        {k: v for k, v in values.items() if k not in FOOT},
        {FOOT[k]: v for k, v in values.items() if k in FOOT},
    )


def update_surface(
    document: Any, surface: str, values: dict[str, float], comment: str = COMMENT
) -> None:
    """Set ``surfaces.<surface>.<name>`` in a round-trip document, each with ``comment``."""
    block = document.get("surfaces", {}).get(surface)
    _set_keys(block, f"surfaces.{surface}", values, comment)


def update_backing(
    document: Any, robot: str, values: dict[str, float], comment: str = COMMENT
) -> None:
    """Set ``robots.<robot>.platform.foot.backing.<name>``, each with ``comment``."""
    if values:
        foot = document["robots"][robot]["platform"]["foot"]
        _set_keys(foot.get("backing"), f"robots.{robot}.platform.foot.backing", values, comment)


def _set_keys(block: Any, where: str, values: dict[str, float], comment: str) -> None:
    from ftfof.pipeline.params_file import yaml_float

    missing = sorted(set(values) - set(block or ()))
    if block is None or missing:
        raise ParamsError(where, f"has no key for {missing} (add them to params.yaml first)")
    for name, value in values.items():
        block[name] = float(f"{value:.6g}")
        # two spaces before the comment, wherever an earlier comment of the key stood
        column = block.lc.col + len(f"{name}: {yaml_float(block[name])}") + 2
        below = _comment_lines_below(block, name)
        block.yaml_add_eol_comment(comment, name, column=column)
        if below:  # ruamel keeps the full-line comments under a key in its end-of-line comment
            block.ca.items[name][2].value += "\n" + below


def _comment_lines_below(block: Any, name: str) -> str:
    """The full-line comments that follow ``name``'s line (kept when its comment is replaced)."""
    token = (block.ca.items.get(name) or [None, None, None])[2]
    if token is None or "\n" not in token.value:
        return ""
    return token.value.split("\n", 1)[1]
