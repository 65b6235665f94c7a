"""The slip test and the identify command's application side: run or read a slip log, estimate
friction and adhesion, write the report, the convergence plot and a surface preset block."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ftfof.config import Params, Surface
from ftfof.data.sliplog import parse_slip
from ftfof.errors import DataError, ParamsError
from ftfof.files import atomic_path, write_json
from ftfof.identify.estimate import Estimate, Track, kalman, least_squares
from ftfof.identify.log import SlipLog, slip_samples
from ftfof.pipeline.params_file import edit_params
from ftfof.sim.bonds import BondLaw
from ftfof.sim.slip import SlipProtocol, adhesion_truth, drag, slip_test
from ftfof.sim.spec import Bench

PROTOCOL = SlipProtocol(
    loads=(-1.0, 0.0, 1.0, 2.0, 3.0, 4.0), speed=0.01, drag=0.008, ankle_stiffness=50.0
)


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
    return slip_test(bench.spec("slip", 0, drag(protocol.speed, protocol.drag)), protocol)


def truth(params: Params, name: str) -> Estimate:
    """mu and F_adh per pad the preset and the bond law imply (:func:`adhesion_truth`)."""
    r = params.selected_robot
    law = BondLaw.from_surface(surface_of(params, name), params.acquire.solver.contact_smoothing)
    area = r.foot.pad_length * r.platform.film.width
    return Estimate(law.friction, adhesion_truth(law, r.pre_pressure, area))


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


def identify(log: SlipLog) -> tuple[Estimate, Track]:
    """Least squares over the slip samples, and the Kalman estimate started from it (the seed's
    filter needs a start near the truth: a window holds one load, so the first windows alone
    cannot give one)."""
    slip = slip_samples(log)
    fn, ft = -log.Fz[slip], np.abs(log.Fx[slip])
    ls = least_squares(fn, ft)
    return ls, kalman(fn, ft, ls)


def report(ls: Estimate, track: Track, true: Estimate | None) -> dict[str, Any]:
    def block(name: str) -> dict[str, float | None]:
        return {
            "estimate": getattr(track.final, name),
            "truth": getattr(true, name) if true else None,
            "least_squares": getattr(ls, name),
        }

    return {"mu": block("mu"), "adhesion": block("adhesion"), "adhesion_unit": "N per pad"}


def write_outputs(out: dict[str, Any], track: Track, json_path: Path, figure: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(6, 5))
    for ax, name, values in (
        (axes[0], "mu", track.mu),
        (axes[1], "adhesion", track.adhesion),
    ):
        ax.plot(track.samples, values, label="Kalman estimate")
        ax.axhline(out[name]["least_squares"], ls=":", color="k", label="least squares")
        if out[name]["truth"] is not None:
            ax.axhline(out[name]["truth"], ls="--", color="g", label="truth")
        ax.set_ylabel("μ" if name == "mu" else "F_adh per pad, N")
    axes[0].legend()
    axes[1].set_xlabel("slip samples seen")
    fig.tight_layout()
    figure.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(figure) as tmp:
        fig.savefig(tmp, format="png", dpi=120)
    plt.close(fig)
    write_json(json_path, out)


def write_surface(params_path: Path, params: Params, name: str, est: Estimate) -> None:
    """Set the surface's friction and the strength whose shear allowance gives F_adh at the
    robot's preload (inverting :func:`adhesion_truth`), comments kept."""
    surface = surface_of(params, name)
    r = params.selected_robot
    area = r.foot.pad_length * r.platform.film.width
    law = BondLaw.from_surface(surface, params.acquire.solver.contact_smoothing)
    s = float(law.preload_factor(r.pre_pressure / area))
    strength = est.mu * est.adhesion / (s * area * surface.shear_capacity_ratio)

    def edit(document: Any) -> None:
        block = document["surfaces"][name]
        block["friction"] = round(est.mu, 4)
        block["strength"] = round(strength, 1)
        for key in ("friction", "strength"):
            block.yaml_add_eol_comment("identified by ftfof identify (reports/identify.json)", key)

    edit_params(params_path, edit)
