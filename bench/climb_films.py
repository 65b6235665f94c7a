"""One climb on several films: does its ending depend on the film's elements? Either a Table I
trajectory's climb (as `ftfof climb` runs it) or the slip scenario's climb under one controller
(as the slip stage runs it), each film in its own process, two at a time. A film is ``N``
(uniform) or ``N@h`` (graded, h mm at the pad's ends; bench/film_elements.py). Results:
docs/decisions/0047-the-climb-needs-forty-film-elements.md.

Run: python bench/climb_films.py TRAJECTORY|slip:CONTROLLER FILM,FILM,... [seconds]
     e.g. python bench/climb_films.py slip:none 30,40,80 4.0
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.film_elements import film_settings
from ftfof.climb.simulate import climb
from ftfof.climb.specs import ClimbSpec, controller_specs
from ftfof.evaluate.pick import Source
from ftfof.pipeline.bench import baseline_trajectories, context_of
from ftfof.pipeline.climb import climb_spec
from ftfof.pipeline.params_file import load_params
from ftfof.pipeline.slip import slip_scenario_spec

ROOT = Path(__file__).resolve().parents[1]


def spec_of(what: str) -> ClimbSpec:
    """``slip:<controller>``: the slip scenario's climb; otherwise a Table I trajectory's."""
    params = load_params(ROOT / "params.yaml")
    if what.startswith("slip:"):
        ctx = context_of(params)
        trajectory = baseline_trajectories(params, ctx)[params.evaluate.slip_scenario.trajectory]
        spec, _ = slip_scenario_spec(params, ctx, trajectory)
        return controller_specs(spec)[what.removeprefix("slip:")]
    return climb_spec(params, Source(baseline=what), ROOT / "data/polish/optimize")[1]


def on_film(spec: ClimbSpec, label: str) -> ClimbSpec:
    """``spec`` climbed with the pads on the film ``label``."""
    return replace(spec, solver=spec.solver.model_copy(update=film_settings(label)))


def run(job: tuple[ClimbSpec, str, float | None]) -> str:
    """One film's climb in a worker: how it ended, how far it got and its wall seconds."""
    spec, label, duration = job
    start = time.perf_counter()
    result = climb(on_film(spec, label), duration=duration)
    end = float(result.channels["t"][-1])
    ending = f"fell: {result.fall_reason}" if result.fell else "held"
    return f"{label:8s} {ending} (to {end:.3f} s simulated, {time.perf_counter() - start:.0f} s)"


def main(what: str, films: list[str], duration: float | None) -> None:
    spec = spec_of(what)
    print(f"{what}: {spec.name}, {'the whole climb' if duration is None else f'{duration} s'}")
    with ProcessPoolExecutor(2) as pool:
        for line in pool.map(run, [(spec, film, duration) for film in films]):
            print(" ", line, flush=True)


if __name__ == "__main__":
    main(
        sys.argv[1],
        sys.argv[2].split(","),
        float(sys.argv[3]) if len(sys.argv) > 3 else None,
    )
