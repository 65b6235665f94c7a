"""What `evaluate` simulates: the optimum, front members, the baselines and the published optimum,
and the same again at the check step and on the check film, each as a spec with its decision
vector where it has one."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ftfof.evaluate.film_check import FILM
from ftfof.evaluate.run import Inputs, decision
from ftfof.evaluate.runs import OPTIMUM, PAPER_OPTIMUM
from ftfof.evaluate.step_check import FINE
from ftfof.sim.spec import Bench, SampleSpec


def evaluation_specs(
    on: Bench,
    inputs: Inputs,
    front_rows: list[int],
    baselines: list[SampleSpec],
    published_optimum: Sequence[float] | None,
    check_step: float | None,
    check_nodes: int | None,
) -> tuple[list[SampleSpec], dict[str, np.ndarray]]:
    """The optimum, the sampled front rows, the ``baselines`` and the ``published_optimum`` (held
    out: simulated, never fitted); Table I's trajectories again at ``check_step`` (sources
    prefixed ``FINE``), and all of them again on ``check_nodes`` film elements (prefixed
    ``FILM``). With the decision vectors by key."""
    specs, controls = front_specs(on, inputs, front_rows)
    specs += baselines
    if published_optimum is not None:
        X = np.asarray(published_optimum, dtype=float)
        spec = on.bezier(PAPER_OPTIMUM, 0, X)
        specs.append(spec)
        controls[spec.key] = X
    variants = []
    if check_step is not None:
        variants += [with_step(s, check_step) for s in specs if s.source != "front"]
    if check_nodes is not None:
        variants += [with_nodes(s, check_nodes) for s in specs]
    for variant in variants:
        original = variant.key.removeprefix(FINE).removeprefix(FILM)
        if original in controls:
            controls[variant.key] = controls[original]
    return specs + variants, controls


def with_step(spec: SampleSpec, step: float) -> SampleSpec:
    """``spec`` simulated with every solver step ``step`` (in every phase too: no
    ``phase_steps``), its source and key prefixed ``FINE`` (the same sensor-noise seed)."""
    return _variant(spec, FINE, step=step, free_step=step, phase_steps={})


def with_nodes(spec: SampleSpec, nodes: int) -> SampleSpec:
    """``spec`` on a uniform film of ``nodes`` elements (the converged reference, whatever the
    acquisition's grading), its source and key prefixed ``FILM``."""
    return _variant(spec, FILM, nodes=nodes, edge_element=None)


def _variant(
    spec: SampleSpec, prefix: str, **solver: float | dict[str, float] | None
) -> SampleSpec:
    """``spec`` with ``solver`` settings changed, its source and key prefixed ``prefix``."""
    changed = spec.solver.model_copy(update=solver)
    return replace(spec, key=prefix + spec.key, source=prefix + spec.source, solver=changed)


def front_specs(
    on: Bench, inputs: Inputs, front_rows: list[int]
) -> tuple[list[SampleSpec], dict[str, np.ndarray]]:
    """Specs of the optimum (source ``optimum``) and of ``front_rows`` (source ``front``), each
    with its front row as sample id, and their decision vectors by key."""
    chosen = inputs.optimum["front_row"]
    specs, controls = [], {}
    for source, row in [(OPTIMUM, chosen), *(("front", r) for r in front_rows)]:
        X = decision(inputs, row)
        spec = on.bezier(source, row, X)
        specs.append(spec)
        controls[spec.key] = X
    return specs, controls
