"""A controller's adaptation: the QP weights its stance feet get from their slip, and the feet
whose servos it anchors (:class:`~ftfof.climb.control.feedforward.FeedForward` composes one with
a re-planning, :mod:`ftfof.climb.control.controllers`).

- :class:`NoAdaptation`: the nominal weights, no foot anchored;
- :class:`WeightAdaptation`: a stance foot detected slipping gets its weights adapted by its
  slip rate (climbing_slip §5), the rate held at its highest until the stance changes (§6.3:
  the paper's weights start anew with each phase), and is anchored until it lifts.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ftfof.climb.control.slip import adapt_weights, slip_rate

Array = NDArray[np.float64]
SLIP_SPAN = 0.02  # m/s: the slip rate's scale above the threshold (slip_rate)


class Adaptation(Protocol):
    """What a controller does to its QP weights under slip, one control step at a time."""

    # The feet whose servos hold them where they are on the wall, whatever the body does (the
    # loop moves their targets with the body's error from its plan, ftfof.climb.targets.Anchors).
    anchored: NDArray[np.bool_]

    def weights(
        self, nominal: Array, slip_velocity: Array, slipping: Array, stance: Array, threshold: float
    ) -> Array:
        """(feet, 2) this step's QP weights from the ``nominal`` ones, with ``slipping`` the
        detector's feet and ``threshold`` its slip velocity (m/s)."""
        ...


@dataclass
class NoAdaptation:
    """The nominal weights throughout; no foot is ever anchored."""

    feet: int
    anchored: NDArray[np.bool_] = field(init=False)

    def __post_init__(self) -> None:
        self.anchored = np.zeros(self.feet, dtype=bool)

    def weights(
        self, nominal: Array, slip_velocity: Array, slipping: Array, stance: Array, threshold: float
    ) -> Array:
        return nominal


@dataclass
class WeightAdaptation:
    """The weights of climbing_slip §5 by each foot's slip rate held through its phase, and a
    slipping foot anchored from its slip until it lifts. On position servos the joint PD, not
    the QP, sets most of a stance foot's tangential force: it holds the foot on the body, so a pad
    that cannot carry its share slides with the body's sag on the other feet's films (the slip
    scenario under `none`: HR's pad 4.5 mm down as the body fell 4.8 mm behind its plan), and
    lower QP weights alone changed little (docs/decisions/0023-anchored-slipping-foot.md)."""

    feet: int
    held_rate: Array = field(init=False)  # each foot's slip rate held this phase
    phase: NDArray[np.bool_] = field(init=False)  # the stance it belongs to
    anchored: NDArray[np.bool_] = field(init=False)

    def __post_init__(self) -> None:
        self.held_rate = np.zeros(self.feet)
        self.phase = np.zeros(self.feet, dtype=bool)
        self.anchored = np.zeros(self.feet, dtype=bool)

    def weights(
        self, nominal: Array, slip_velocity: Array, slipping: Array, stance: Array, threshold: float
    ) -> Array:
        rate = self._hold_rate(slip_velocity, slipping, stance, threshold)
        weights = adapt_weights(nominal, rate)
        self.anchored = (self.anchored | slipping) & stance
        return weights

    def _hold_rate(
        self, slip_velocity: Array, slipping: Array, stance: Array, threshold: float
    ) -> Array:
        """Each foot's slip rate, held at its highest since the stance last changed: the
        paper's weights stay adapted through the phase once a slip has stopped, and start anew
        with each phase (climbing_slip §6.3: the weight-only controller slips again at the next
        phase for that reason)."""
        stance = np.asarray(stance, dtype=bool)
        if not np.array_equal(stance, self.phase):
            self.held_rate = np.zeros_like(self.held_rate)
            self.phase = stance.copy()
        rate = slip_rate(slip_velocity, threshold, SLIP_SPAN) * slipping
        self.held_rate = np.maximum(self.held_rate, rate)
        return self.held_rate
