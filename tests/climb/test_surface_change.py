"""climb.surface_change: refused in one line naming its key; applied, it moves one pad only."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ftfof.climb.simulate import climb
from ftfof.climb.surface import SurfaceSwitch
from ftfof.config import LEG_NAMES
from ftfof.config.validate import parse_params
from ftfof.errors import ParamsError
from tests.climb.helpers import spec_of


def _with_change(params_dict: dict, **change: object) -> dict:
    params_dict["climb"]["surface_change"] = {"foot": "FL", "time": 3.0, "surface": "glass"}
    params_dict["climb"]["surface_change"].update(change)
    return params_dict


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"foot": "ML"}, "climb.surface_change.foot"),
        ({"surface": "ice"}, "climb.surface_change.surface"),
        ({"time": 0.0}, "climb.surface_change.time"),
    ],
)
def test_a_bad_surface_change_is_one_line_naming_its_key(params_dict, change, key):
    with pytest.raises(ParamsError) as err:
        parse_params(_with_change(params_dict, **change))
    message = str(err.value)
    assert key in message and "\n" not in message


def test_a_surface_change_after_the_climb_is_refused_before_it_runs(params_dict):
    params = parse_params(_with_change(params_dict, time=1e3))
    with pytest.raises(ParamsError) as err:
        spec_of(params)
    assert err.value.where == "climb.surface_change.time" and "\n" not in str(err.value)


def test_a_surface_change_resolves_its_foot_and_preset(params_dict):
    params = parse_params(_with_change(params_dict, foot="HR", time=2.5))
    assert spec_of(params).switch == SurfaceSwitch(
        LEG_NAMES.index("HR"), 2.5, params.surfaces["glass"]
    )


@pytest.mark.integration
def test_a_pad_switched_to_a_weaker_surface_carries_less_and_slides_further(params):
    """Every pad bonded, the robot settling: at 0.3 s HR's pad moves to a wall of 2 % of the
    strength. Its bonds soften (they hold: the fracture energy is the old one's), so the pad
    sheds its share of the weight to the others and slides further down the wall. It keeps the
    friction of its press, which the weak wall does not change (docs/decisions/0027): it sheds
    40 % of its shear, not more."""
    spec = spec_of(params)
    weak = spec.surface.model_copy(update={"strength": 0.02 * spec.surface.strength})
    hr = LEG_NAMES.index("HR")
    runs = [
        climb(replace(spec, switch=s), duration=0.8) for s in (None, SurfaceSwitch(hr, 0.3, weak))
    ]
    shear, slide = [], []
    for run in runs:
        c = run.channels
        assert run.ok and not run.fell
        before, end = np.searchsorted(c["t"], [0.29, 0.79])
        shear.append(abs(c["force"][end, 2 * hr]))
        slide.append(abs(c["foot"][end, 2 * hr] - c["foot"][before, 2 * hr]))
    assert shear[1] < 0.65 * shear[0]
    assert slide[1] > slide[0] + 1e-4
