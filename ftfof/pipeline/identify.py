"""The slip test and the identify command's application side: run or read a slip log, estimate
friction and adhesion, write the report, the convergence plot and a surface preset block."""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import pandas as pd
import yaml
from matplotlib.figure import Figure

from ftfof.config import Params, Surface
from ftfof.data.sliplog import parse_slip
from ftfof.errors import DataError, ParamsError
from ftfof.files import atomic_path, save_figure
from ftfof.identify.estimate import Estimate
from ftfof.identify.log import SlipLog
from ftfof.pipeline.params_file import edit_params
from ftfof.pipeline.summaries import write_metrics
from ftfof.sim import identified
from ftfof.sim.bonds import BondLaw
from ftfof.sim.identified import PROTOCOL, simulated_log
from ftfof.sim.slip import SlipProtocol, adhesion_truth
from ftfof.sim.spec import Bench

COMMENT = "identified by ftfof identify (reports/identify.json)"


@dataclass(frozen=True)
class IdentifyPaths:
    report: Path  # reports/identify.json (its summary beside it)
    folder: Path  # the stage's folder: the plot and the preset block

    @property
    def figure(self) -> Path:
        return self.folder / "convergence.png"

    @property
    def preset(self) -> Path:
        return self.folder / "surface.yaml"


def surface_of(params: Params, name: str) -> Surface:
    if name not in params.surfaces:
        raise ParamsError("--surface", f"no surface {name!r} (have {', '.join(params.surfaces)})")
    return params.surfaces[name]


def simulate_slip(params: Params, name: str, protocol: SlipProtocol = PROTOCOL) -> SlipLog:
    """The slip test of the selected robot's pad on surface ``name``."""
    bench = Bench(
        params.selected_robot,
        surface_of(params, name),
        params.platform,
        params.acquire,
        params.base.seed,
    )
    return simulated_log(bench, protocol)


def law_of(params: Params, name: str) -> BondLaw:
    """Surface ``name``'s bond law at the acquisition's contact smoothing."""
    return BondLaw.from_surface(surface_of(params, name), params.acquire.solver.contact_smoothing)


def truth(params: Params, name: str) -> Estimate:
    """mu and F_adh per pad the preset and the bond law imply at the test's drag speed
    (:func:`ftfof.sim.identified.truth`)."""
    return identified.truth(law_of(params, name), params.selected_robot)


def quasi_static(params: Params, name: str, est: Estimate, simulated: bool) -> dict[str, Any]:
    """The report's F_adh,0 block: the estimate taken back to no rate through the preset's rate
    law at the protocol's speed (a log is taken to follow `ftfof slip-test`'s protocol), beside
    the preset's F_adh,0 where the log is simulated."""
    law, robot = law_of(params, name), params.selected_robot
    true = adhesion_truth(law, robot.pre_pressure, robot.pad_area) if simulated else None
    return {
        "estimate": identified.quasi_static(law, est.adhesion, PROTOCOL.speed),
        "truth": true,
        "speed": PROTOCOL.speed,
    }


def rate_law(params: Params, name: str, speeds: list[float]) -> dict[str, Any]:
    """The rate law's n and v* from simulated slip tests at two ``speeds``, F_adh,0 taken as the
    preset's (:func:`ftfof.sim.identified.rate_law`), beside the preset's n and v*."""
    from ftfof.identify import fit

    law, robot = law_of(params, name), params.selected_robot
    drags = {
        v: fit.identify(simulate_slip(params, name, replace(PROTOCOL, speed=v)))[1].final.adhesion
        for v in speeds
    }
    got = identified.rate_law(law, adhesion_truth(law, robot.pre_pressure, robot.pad_area), drags)
    return {
        "speeds": sorted(drags),
        "adhesion": [drags[v] for v in sorted(drags)],
        "exponent": {"estimate": got.exponent, "truth": law.rate_exponent},
        "rate_speed": {"estimate": got.speed, "truth": law.rate_speed},
    }


def write_log(log: SlipLog, path: Path) -> None:
    with atomic_path(path) as tmp:
        pd.DataFrame(log.columns()).to_csv(tmp, index=False)


def read_log(path: Path) -> SlipLog:
    if not path.is_file():
        raise DataError(str(path), "no such file")
    try:
        df = pd.read_csv(path)
    except Exception as err:  # any reader failure is a malformed file
        raise DataError(str(path), f"unreadable ({str(err).splitlines()[0]})") from None
    return parse_slip(df, str(path))


def read_calibration(path: Path, surface: str) -> float:
    """The pull-off strength sigma that ``ftfof calibrate`` fitted (or held) for ``surface``."""
    if not path.is_file():
        raise DataError(str(path), "no such file (run `ftfof calibrate` first)")
    try:
        fit = json.loads(path.read_text())
        strength = {**fit["fixed"], **fit["values"]}.get("strength")
        fitted_on = fit["surface"]
    except (json.JSONDecodeError, KeyError, TypeError) as err:
        raise DataError(str(path), f"not a calibration report ({err})") from None
    if fitted_on != surface:
        raise DataError(str(path), f"calibrates surface {fitted_on!r}, not {surface!r}")
    if strength is None:
        raise DataError(str(path), "has no strength (fitted or fixed)")
    return float(strength)


def preset(
    params: Params, name: str, source: str, est: Estimate, pull_off: float | None = None
) -> dict[str, Any]:
    """Surface ``name``'s preset with the identified mu and quasi-static F_adh,0 in ``est``
    (:func:`ftfof.sim.identified.identified_preset`)."""
    law, robot = law_of(params, name), params.selected_robot
    return identified.identified_preset(law, robot, surface_of(params, name), source, est, pull_off)


def write_outputs(
    out: dict[str, Any], figure: Figure, block: dict[str, Any], paths: IdentifyPaths
) -> None:
    """The report and its summary, the convergence plot and the preset block, all built."""
    save_figure(figure, paths.figure)
    with atomic_path(paths.preset) as tmp:
        tmp.write_text(yaml.safe_dump({out["surface"]: block}, sort_keys=False))
    write_metrics("identify", paths.report, out)


def write_off(paths: IdentifyPaths) -> None:
    """What the pipeline's stage leaves when ``identify.enabled`` is false: a report saying so,
    and the stage's folder empty."""
    paths.folder.mkdir(parents=True, exist_ok=True)
    for stale in (paths.figure, paths.preset):
        stale.unlink(missing_ok=True)
    write_metrics("identify", paths.report, {"enabled": False})


def write_surface(params_path: Path, name: str, block: dict[str, Any], current: Surface) -> None:
    """Set the preset's values that identify changed, each with a comment naming it; the rest
    of params.yaml as it is."""
    changed = {k: v for k, v in block.items() if getattr(current, k) != v}

    def edit(document: Any) -> None:
        surface = document["surfaces"][name]
        for key, value in changed.items():
            surface[key] = value
            surface.yaml_add_eol_comment(COMMENT, key)

    edit_params(params_path, edit)
