"""What the model can say about Table I's ordering and the paper's -28 % (docs/simulator.md).

The polynomial, the cycloid and the paper's published optimum Pf simulated with one value changed
from params.yaml at a time: the film, the adhesive (G, the rate factor) and the foot's geometry.
Prints each row's polynomial pull, the cycloid's and Pf's change against it, and Pf's film bend.
Pf stays held out: this measures, it fits nothing.

Run: python bench/calibration_sensitivity.py   (about 2 min on 2 cores)
"""

from __future__ import annotations

import copy
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.config.validate import parse_params
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import read_yaml
from ftfof.sim.pool import run_all
from ftfof.sim.spec import baseline_specs

FILM_125UM = {"FILM.thickness": 1.25e-4, "FILM.mass_per_length": 0.010}
ROWS: list[tuple[str, dict[str, float]]] = [
    ("none (the fitted default)", {}),
    ("125 um film, this surface", FILM_125UM),
    *((f"G = {g:g} J/m^2", {"SURFACE.fracture_energy": g}) for g in (30.0, 50.0, 120.0)),
    *((f"rate exponent n = {n:g}", {"SURFACE.rate_exponent": n}) for n in (0.2, 0.8)),
    *((f"rate speed v* = {v:g} m/s", {"SURFACE.rate_speed": v}) for v in (0.01, 0.5)),
    *((f"ankle height {1e3 * h:g} mm", {"FOOT.ankle_height": h}) for h in (0.008, 0.025, 0.06)),
    *((f"grip length {1e3 * g:g} mm", {"FOOT.grip_length": g}) for g in (0.0025, 0.01)),
    *((f"ankle stiffness {k:g} N m/rad", {"FOOT.ankle_stiffness": k}) for k in (0.1, 2.0, 10.0)),
]


def changed(raw: dict, update: dict[str, float]) -> dict:
    """``raw`` with each PREFIX.key of ``update`` set (FILM, FOOT: the robot's platform)."""
    out = copy.deepcopy(raw)
    robot, surface = out["robots"][out["robot"]], out["surfaces"][out["surface"]]
    blocks = {
        "FILM": robot["platform"]["film"],
        "FOOT": robot["platform"]["foot"],
        "SURFACE": surface,
    }
    for dotted, value in update.items():
        block, key = dotted.split(".")
        blocks[block][key] = value
    return out


def measure(raw: dict) -> tuple[float, float, float, float]:
    """Polynomial pull (N), cycloid and Pf change against it, Pf's min bend radius (m)."""
    params = parse_params(raw, "params.yaml, changed")
    ctx = context_of(params)
    on = bench(params, ctx)
    specs = baseline_specs(on, baseline_trajectories(params, ctx), ["polynomial", "cycloidal"])
    specs.append(on.bezier("paper_optimum", 0, np.array(ctx.robot.published_optimum)))
    poly, cyc, pf = run_all(specs)
    for r in (poly, cyc, pf):
        if not r.ok:
            raise RuntimeError(f"{r.source}: {r.error}")
    pull = poly.scalars["peak_detachment"]
    return (
        pull,
        cyc.scalars["peak_detachment"] / pull - 1,
        pf.scalars["peak_detachment"] / pull - 1,
        pf.scalars["min_bend_radius"],
    )


def main() -> None:
    raw = read_yaml(Path(__file__).resolve().parents[1] / "params.yaml")
    print(
        f"{'changed from params.yaml':<30} {'poly [N]':>9} {'cycloid':>9} {'Pf':>9} {'Pf film':>9}"
    )
    print(f"{'Table I (the paper)':<30} {7.49:9.2f} {'-3.3 %':>9} {'-28 %':>9} {'':>9}")
    for label, update in ROWS:
        pull, cyc, pf, bend = measure(changed(raw, update))
        print(f"{label:<30} {pull:9.2f} {100 * cyc:+8.1f}% {100 * pf:+8.1f}% {1e3 * bend:6.2f} mm")


if __name__ == "__main__":
    main()
