"""Evaluate's variants of a run: the check film's elements (the check step's are in
test_step_check.py)."""

from dataclasses import replace

import numpy as np

from ftfof.evaluate.specs import with_nodes
from ftfof.pipeline.bench import bench, context_of
from ftfof.sim.bonds import BondLaw
from ftfof.sim.model import build


def test_the_check_film_is_uniform_whatever_the_acquisitions_grading(params):
    """Evaluate's check film is the converged reference, N uniform elements: a graded acquisition
    film (``edge_element``) does not carry over, or 80 elements of 1.25 mm would not fit the pad."""
    ctx = context_of(params)
    spec = bench(params, ctx).bezier("pf", 0, np.asarray(ctx.robot.published_optimum))
    grading = {"nodes": 30, "edge_element": 1.25e-3}
    graded = replace(spec, solver=spec.solver.model_copy(update=grading))
    check = with_nodes(graded, 80)
    assert check.solver.nodes == 80 and check.solver.edge_element is None
    assert check.key == "film:pf:0" and graded.solver.edge_element == 1.25e-3
    built = build(check, BondLaw.from_surface(check.surface, check.solver.contact_smoothing))
    np.testing.assert_allclose(np.diff(built.x_ref), built.x_ref[-1] / 80)
