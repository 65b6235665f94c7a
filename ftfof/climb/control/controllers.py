"""The climb's controllers by name (``climb.controller``, the CLI's ``--controller``): each is
one composition of an adaptation (:mod:`ftfof.climb.control.adaptation`) and a re-planning
(:mod:`ftfof.climb.control.replanning`), the parts
:class:`~ftfof.climb.control.feedforward.FeedForward` runs each control step.

- ``none``: the QP at the nominal weights and the nominal pads;
- ``weights``: the weights adapted under slip, the slipping foot anchored;
- ``replan``: the slipping foot's pad estimated and believed, and the CoM re-planner asked;
- ``both``: the two together.
"""

from __future__ import annotations

from collections.abc import Callable

from ftfof.climb.control.adaptation import Adaptation, NoAdaptation, WeightAdaptation
from ftfof.climb.control.replan import Replanner
from ftfof.climb.control.replanning import NoReplanning, PadReplanning, Replanning

# a controller's parts for ``feet`` feet, re-planning with ``replanner`` where it re-plans
Composition = Callable[[int, Replanner], tuple[Adaptation, Replanning]]

COMPOSITIONS: dict[str, Composition] = {
    "none": lambda feet, replanner: (NoAdaptation(feet), NoReplanning()),
    "weights": lambda feet, replanner: (WeightAdaptation(feet), NoReplanning()),
    "replan": lambda feet, replanner: (NoAdaptation(feet), PadReplanning(replanner)),
    "both": lambda feet, replanner: (WeightAdaptation(feet), PadReplanning(replanner)),
}


def compose(name: str, feet: int, replanner: Replanner) -> tuple[Adaptation, Replanning]:
    """Controller ``name``'s adaptation and re-planning (a name not in COMPOSITIONS: KeyError,
    which the params and the CLI refuse first)."""
    return COMPOSITIONS[name](feet, replanner)
