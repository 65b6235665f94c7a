"""Does the platform's answer depend on the solver's step? (docs/simulator.md, "Time step").

The solver takes ``acquire.solver.step`` while bonds break or the pad lands. Pull, detachment
jitter (fsj, the body's peak acceleration) and force jitter (fs7, eq. 16's exceedances of the
pull's second derivative) are read in that phase. This script simulates the polynomial baseline
and a chosen optimum (its nominal run and ``--copies`` perturbed copies, as the simulator check
draws them) at the default step and at finer ones, and prints each measure, its spread over the
copies, the optimum's change against the polynomial and the cost per run as a ratio to the
default step's (measured in this process, serially).

Run: python bench/step_convergence.py [OPTIMUM_JSON] [--steps 5e-4,2.5e-4,1.25e-4,6.25e-5]
     (default: data/polish/optimize/optimum.json; about 1 min on one core)
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from ftfof.data import targets
from ftfof.pipeline.bench import baseline_specs, baseline_trajectories, bench
from ftfof.pipeline.params_file import parse_params, read_yaml
from ftfof.pipeline.simcheck import perturbed_runs
from ftfof.robot import robot_context
from ftfof.sim.simulate import simulate
from ftfof.trajectory.bezier import DECISION_NAMES

MEASURES = ("pull", "body_acc", "jitter")  # full-rate targets whose maxima are fs1, fsj, fs7
LABELS = {"pull": "fs1 N", "body_acc": "fsj m/s²", "jitter": "fs7"}


def peaks(spec, T3: float) -> tuple[dict[str, float], float]:
    """The maxima of MEASURES over one run, and its seconds."""
    started = time.perf_counter()
    result = simulate(spec)
    seconds = time.perf_counter() - started
    if not result.ok:
        raise SystemExit(f"{spec.key}: simulation failed ({result.error})")
    series = targets.full_rate(result.channels, T3)
    return {m: float(np.max(series[m])) for m in MEASURES}, seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("optimum", nargs="?", default=ROOT / "data/polish/optimize/optimum.json")
    parser.add_argument("--steps", default="5e-4,2.5e-4,1.25e-4,6.25e-5")
    parser.add_argument("--copies", type=int, default=5)
    args = parser.parse_args()
    raw = read_yaml(ROOT / "params.yaml")
    optimum = json.loads(Path(args.optimum).read_text())
    X = np.array([optimum["decision"][n] for n in DECISION_NAMES])
    baseline = None
    print(f"optimum: {args.optimum} (row {optimum['front_row']}); {args.copies} copies")
    for step in (float(s) for s in args.steps.split(",")):
        solver = {**raw["acquire"]["solver"], "step": step}
        params = parse_params({**raw, "acquire": {**raw["acquire"], "solver": solver}}, "bench")
        ctx = robot_context(params)
        on = bench(params, ctx)
        T3 = ctx.policy.timing.T3
        (poly,) = baseline_specs(on, baseline_trajectories(params, ctx), ["polynomial"])
        reference, _ = peaks(poly, T3)
        rng = np.random.default_rng(11)
        runs = perturbed_runs(ctx.policy, X, params.optimize.verify_repeatability, args.copies, rng)
        measured = [peaks(on.bezier(f"copy{k}", 0, x), T3) for k, x in enumerate(runs)]
        values = {m: np.array([v[m] for v, _ in measured]) for m in MEASURES}
        per_run = float(np.mean([s for _, s in measured]))
        baseline = baseline or per_run
        print(f"step {step:.3g} s: {per_run:.2f} s a run ({per_run / baseline:.2f}x the first)")
        for m in MEASURES:
            v = values[m]
            change = 100 * (v[0] / reference[m] - 1)
            print(
                f"  {LABELS[m]:<9} polynomial {reference[m]:7.2f} | optimum {v[0]:7.2f} "
                f"({change:+5.1f} %), copies' mean {v.mean():7.2f} sd {v.std(ddof=1):5.2f}"
            )


if __name__ == "__main__":
    main()
