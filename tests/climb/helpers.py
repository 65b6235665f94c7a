"""A climb of one of the params' baselines, built as the `climb` command builds it."""

from __future__ import annotations

from ftfof.climb.model import ClimbSpec
from ftfof.config import Params
from ftfof.evaluate.pick import Source
from ftfof.pipeline.climb import climb_spec
from tests.conftest import ROOT


def spec_of(params: Params, baseline: str = "polynomial", **changes: object) -> ClimbSpec:
    """``baseline``'s climb spec; ``changes`` replace ClimbSpec fields (surface, climb, ...)."""
    from dataclasses import replace

    _, spec = climb_spec(params, Source(baseline=baseline), ROOT / "data" / "polish" / "optimize")
    return replace(spec, **changes)
