"""A controller's re-planning: what it does when a stance foot starts to slip
(:class:`~ftfof.climb.control.feedforward.FeedForward` composes one with an adaptation,
:mod:`ftfof.climb.control.controllers`).

- :class:`NoReplanning`: the nominal pads and the loop's plan throughout;
- :class:`PadReplanning`: the slipping foot's pad as estimated from its last ESTIMATE_SAMPLES
  force samples (:meth:`FeedForward.step <ftfof.climb.control.feedforward.FeedForward.step>`
  estimates every slip, whatever the controller) replaces the believed pad in the QP and goes
  to the re-planner (:mod:`ftfof.climb.control.replan`), whose plan the loop then tracks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.replan import BodyPlan, Replanner, ReplanRequest
from ftfof.climb.control.slip import cone_of, estimate_adhesion
from ftfof.climb.control.state import Counts, Pads, Sensed
from ftfof.identify.estimate import Estimate

Array = NDArray[np.float64]


class Replanning(Protocol):
    """What a controller does about the feet that started to slip this control step."""

    def replan(
        self, now: Sensed, estimated: dict[int, Estimate], believed: Pads, counts: Counts
    ) -> tuple[BodyPlan, BodyPlan | None]:
        """The plan to track this step and the new plan the loop gets (None: keep its own),
        after the feet that started to slip this step, ``estimated`` their pads as the cone
        takes them (:func:`believable`); ``believed`` changes in place with what it learns."""
        ...


class NoReplanning:
    """A slip changes neither the pads the QP believes nor the plan."""

    def replan(
        self, now: Sensed, estimated: dict[int, Estimate], believed: Pads, counts: Counts
    ) -> tuple[BodyPlan, BodyPlan | None]:
        return now.plan, None


@dataclass
class PadReplanning:
    """Each slipping foot's pad estimated and believed, and the ``replanner`` asked for a plan."""

    replanner: Replanner

    def replan(
        self, now: Sensed, estimated: dict[int, Estimate], believed: Pads, counts: Counts
    ) -> tuple[BodyPlan, BodyPlan | None]:
        plan, new_plan = now.plan, None
        for foot, got in estimated.items():
            new_plan = self._replan(now, foot, got, plan, believed, counts)
            plan = new_plan or plan
        return plan, new_plan

    def _replan(
        self, now: Sensed, foot: int, got: Estimate, plan: BodyPlan, believed: Pads, counts: Counts
    ) -> BodyPlan | None:
        """Believe the slipping foot's estimated pad ``got`` and ask for a plan."""
        # the pull-off and F_adh are both s x strength x area: they scale together
        believed.pull_off[foot] *= got.adhesion / believed.adhesion[foot]
        believed.friction[foot], believed.adhesion[foot] = got.mu, got.adhesion
        counts.estimates += 1
        request = ReplanRequest(
            now.time,
            foot,
            believed.friction.copy(),
            believed.adhesion.copy(),
            now.stance.copy(),
            now.feet.copy(),
            now.body.copy(),
            now.body_rate.copy(),
            plan,
            believed.pull_off.copy(),
        )
        new = self.replanner(request)
        counts.replans += new is not None
        return new


def believable(believed: Pads, foot: int, fit: Estimate, fn: Array, ft: Array) -> Estimate | None:
    """The pad's (mu, F_adh) as the cone takes them, from its tangential-form ``fit``
    (:func:`~ftfof.climb.control.slip.fit_pad`) of the window ``fn``, ``ft``. Where the fit gives
    mu <= 0 or F_adh <= 0, the pad is losing its bonds as it slides (a peel under shear, not a
    slide on a fixed cone); its mu stays believed and only its F_adh, what it still holds, is
    fitted. None if even that is off the range (F_adh not finite, or <= 0)."""
    got = cone_of(fit)
    if math.isfinite(got.mu) and math.isfinite(got.adhesion) and got.mu > 0 < got.adhesion:
        return got
    mu = float(believed.friction[foot])
    adhesion = estimate_adhesion(fn, ft, mu)
    return Estimate(mu, adhesion) if math.isfinite(adhesion) and adhesion > 0 else None
