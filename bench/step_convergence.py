"""Does the platform's answer depend on the solver's step? (docs/simulator.md, "Time step").

Pull, detachment jitter (fsj, the body's peak acceleration), force jitter (fs7, eq. 16's
exceedances of the pull's second derivative) and the landing press, for the polynomial baseline
and a chosen optimum (its nominal run and ``--copies`` perturbed copies, as the simulator check
draws them), at each of ``--steps`` taken throughout the run; with ``--free-step`` the solver
takes that step wherever no bond is about to break and the pad is not landing (the mixed steps
the platform used before, whose changes of step disturb the body). Prints each figure, its
spread over the copies, the optimum's change against the polynomial and the cost per run as a
ratio to the first step's (measured in this process, serially).

Run: python bench/step_convergence.py [OPTIMUM_JSON] [--steps 1e-3,5e-4,2.5e-4,1.25e-4]
     [--free-step 2e-3]   (default: data/polish/optimize/optimum.json; about 2 min on one core)
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.config.validate import parse_params
from ftfof.evaluate.simcheck import perturbed_runs
from ftfof.evaluate.step_check import CHECKED, checked_figures
from ftfof.pipeline import catalog
from ftfof.pipeline.artefacts import OPTIMUM_FILE
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import read_yaml
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import baseline_specs
from ftfof.trajectory.bezier import DECISION_NAMES

ROOT = Path(__file__).resolve().parents[1]
LABELS = {c: f"{c} {unit}".strip() for c, _, unit in CHECKED}


def peaks(spec, T3: float) -> tuple[dict[str, float], float]:
    """The CHECKED figures of one run, and its seconds."""
    started = time.perf_counter()
    result = simulate(spec)
    seconds = time.perf_counter() - started
    if not result.ok:
        raise SystemExit(f"{spec.key}: simulation failed ({result.error})")
    return checked_figures(result.channels, result.scalars, T3), seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "optimum", nargs="?", default=ROOT / catalog.path("polish_optimize") / OPTIMUM_FILE
    )
    parser.add_argument("--steps", default="1e-3,5e-4,2.5e-4,1.25e-4")
    parser.add_argument("--free-step", type=float, default=None)
    parser.add_argument("--copies", type=int, default=5)
    args = parser.parse_args()
    raw = read_yaml(ROOT / "params.yaml")
    optimum = json.loads(Path(args.optimum).read_text())
    X = np.array([optimum["decision"][n] for n in DECISION_NAMES])
    baseline = None
    print(f"optimum: {args.optimum} (row {optimum['front_row']}); {args.copies} copies")
    for step in (float(s) for s in args.steps.split(",")):
        free = step if args.free_step is None else args.free_step
        solver = {**raw["acquire"]["solver"], "step": step, "free_step": free}
        changed = {
            **raw,
            "acquire": {**raw["acquire"], "solver": solver},
            "evaluate": {**raw["evaluate"], "check_step": None},  # any step may be tried here
        }
        params = parse_params(changed, "bench")
        ctx = context_of(params)
        on = bench(params, ctx)
        T3 = ctx.policy.timing.T3
        (poly,) = baseline_specs(on, baseline_trajectories(params, ctx), ["polynomial"])
        reference, _ = peaks(poly, T3)
        rng = np.random.default_rng(11)
        runs = perturbed_runs(ctx.policy, X, params.optimize.verify_repeatability, args.copies, rng)
        measured = [peaks(on.bezier(f"copy{k}", 0, x), T3) for k, x in enumerate(runs)]
        values = {m: np.array([v[m] for v, _ in measured]) for m in LABELS}
        per_run = float(np.mean([s for _, s in measured]))
        baseline = baseline or per_run
        print(
            f"step {step:.3g} s (free {free:.3g} s): {per_run:.2f} s a run "
            f"({per_run / baseline:.2f}x the first)"
        )
        for m in LABELS:
            v = values[m]
            change = 100 * (v[0] / reference[m] - 1)
            print(
                f"  {LABELS[m]:<24} polynomial {reference[m]:7.2f} | optimum {v[0]:7.2f} "
                f"({change:+5.1f} %), copies' mean {v.mean():7.2f} sd {v.std(ddof=1):5.2f}"
            )


if __name__ == "__main__":
    main()
