"""The controllers by name: each is one composition of an adaptation and a re-planning, and each
part does its one job alone (the weights under slip; the pads and the plan after one)."""

from __future__ import annotations

from typing import get_args

import numpy as np
import pytest

from ftfof.climb.control.adaptation import NoAdaptation, WeightAdaptation
from ftfof.climb.control.controllers import COMPOSITIONS, compose
from ftfof.climb.control.feedforward import NOMINAL_WEIGHTS
from ftfof.climb.control.replanning import NoReplanning, PadReplanning
from ftfof.climb.control.state import Counts, Pads, Sensed
from ftfof.climb.outcome import CONTROLLERS
from ftfof.config.stages import Climb, Controller
from ftfof.identify.estimate import Estimate
from tests.climb.control.stances import ADHESION, FRICTION, PULL_OFF

THRESHOLD = Climb().slip_threshold
NOMINAL = np.tile(NOMINAL_WEIGHTS, (4, 1))
STANCE = np.ones(4, dtype=bool)
FR = 1


def _plan(t):
    return np.zeros_like(t), np.zeros_like(t)


def _new_plan(t):
    return np.ones_like(t), np.zeros_like(t)


def _window(leg):
    fn = np.linspace(-2.0, 4.0, 15)
    return fn, 0.3 * (fn + 5.0)  # a pad of mu 0.3, F_adh 5 N


def _estimated():
    """FR's pad as the controller estimated it (mu 0.3, F_adh 5 N as the cone's shift)."""
    return {FR: Estimate(0.3, 5.0)}


def _pads():
    return Pads(np.full(4, FRICTION), np.full(4, ADHESION), np.full(4, PULL_OFF))


def _now(plan=_plan):
    feet = np.array([0.1, 0.1, -0.1, -0.1])
    return Sensed(0.5, np.zeros(3), np.zeros(3), plan, STANCE, feet, _window)


def test_the_names_are_the_params_controller_values():
    assert tuple(COMPOSITIONS) == get_args(Controller) == CONTROLLERS


@pytest.mark.parametrize(
    ("name", "adaptation", "replanning"),
    [
        ("none", NoAdaptation, NoReplanning),
        ("weights", WeightAdaptation, NoReplanning),
        ("replan", NoAdaptation, PadReplanning),
        ("both", WeightAdaptation, PadReplanning),
    ],
)
def test_each_name_builds_its_adaptation_and_its_replanning(name, adaptation, replanning):
    def replanner(request):
        return None

    got_adaptation, got_replanning = compose(name, 4, replanner)
    assert type(got_adaptation) is adaptation and type(got_replanning) is replanning
    assert got_adaptation.anchored.tolist() == [False] * 4
    if replanning is PadReplanning:
        assert got_replanning.replanner is replanner


def test_an_unknown_name_is_refused():
    with pytest.raises(KeyError):
        compose("reflex", 4, lambda request: None)


def test_the_weight_adaptation_alone_moves_the_slipping_foots_load_toward_the_normal():
    adaptation = WeightAdaptation(4)
    slipping = np.array([False, True, False, False])
    velocity = np.array([0.0, 3 * THRESHOLD, 0.0, 0.0])
    weights = adaptation.weights(NOMINAL, velocity, slipping, STANCE, THRESHOLD)
    assert weights[FR, 0] > NOMINAL[FR, 0] and weights[FR, 1] < NOMINAL[FR, 1]
    assert np.array_equal(np.delete(weights, FR, 0), np.delete(NOMINAL, FR, 0))
    assert adaptation.anchored.tolist() == [False, True, False, False]


def test_no_adaptation_keeps_the_nominal_weights_under_slip():
    adaptation = NoAdaptation(4)
    slipping = np.array([False, True, False, False])
    velocity = np.array([0.0, 3 * THRESHOLD, 0.0, 0.0])
    weights = adaptation.weights(NOMINAL, velocity, slipping, STANCE, THRESHOLD)
    assert weights is NOMINAL and not adaptation.anchored.any()


def test_the_replanning_alone_believes_the_estimate_and_replaces_the_plan():
    seen = []

    def replanner(request):
        seen.append(request)
        return _new_plan

    believed, counts = _pads(), Counts()
    plan, new = PadReplanning(replanner).replan(_now(), _estimated(), believed, counts)
    assert plan is _new_plan and new is _new_plan
    assert seen[0].plan is _plan and seen[0].foot == FR
    assert believed.friction[FR] == 0.3 and believed.adhesion[FR] == 5.0
    assert believed.friction[0] == FRICTION  # the others stay nominal
    assert counts.estimates == 1 and counts.replans == 1


def test_a_replanner_that_keeps_the_plan_leaves_the_loops_plan():
    believed, counts = _pads(), Counts()
    replanning = PadReplanning(lambda request: None)
    plan, new = replanning.replan(_now(), _estimated(), believed, counts)
    assert plan is _plan and new is None
    assert counts.estimates == 1 and counts.replans == 0


def test_no_replanning_keeps_the_pads_and_the_plan_when_a_foot_slips():
    believed, counts = _pads(), Counts()
    plan, new = NoReplanning().replan(_now(), _estimated(), believed, counts)
    assert plan is _plan and new is None
    assert np.array_equal(believed.friction, _pads().friction) and counts == Counts()
