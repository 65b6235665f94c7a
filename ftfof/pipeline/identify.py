"""The slip test and the identify command's application side: the slip bench of a surface preset
(:mod:`ftfof.sim.identified` runs and judges it), slip logs read and written, the report, the
convergence plot, the surface preset block and its edit of params.yaml."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd
import yaml
from matplotlib.figure import Figure

from ftfof.config import Params, Surface
from ftfof.data.sliplog import parse_slip
from ftfof.errors import DataError, ParamsError
from ftfof.files import atomic_path, save_figure
from ftfof.identify.calibration import fitted_strength
from ftfof.identify.log import SlipLog
from ftfof.pipeline.params_file import edit_params
from ftfof.pipeline.summaries import write_metrics
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


def slip_bench(params: Params, name: str) -> Bench:
    """The bench of the slip test of the selected robot's pad on surface ``name``."""
    return Bench(
        params.selected_robot,
        surface_of(params, name),
        params.platform,
        params.acquire,
        params.base.seed,
    )


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
    """The pull-off strength sigma that ``ftfof calibrate`` fitted (or held) for ``surface``
    (:func:`ftfof.identify.calibration.fitted_strength`)."""
    if not path.is_file():
        raise DataError(str(path), "no such file (run `ftfof calibrate` first)")
    try:
        fit = json.loads(path.read_text())
    except json.JSONDecodeError as err:
        raise DataError(str(path), f"not a calibration report ({err})") from None
    return fitted_strength(fit, surface, str(path))


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
