"""`calibrate --write-params` sets the fitted keys in place, or refuses with a one-line error."""

from pathlib import Path

import pytest
import yaml

from ftfof.errors import ParamsError
from ftfof.pipeline.params_file import edit_yaml
from stages.calibrate import update_surface

PARAMS = "surfaces:\n  acrylic:\n    strength: 1.0  # a note\n    friction: 0.6\nrobot: m3f\n"


def _rewrite(values: dict[str, float]) -> str:
    return edit_yaml(PARAMS, lambda doc: update_surface(doc, "acrylic", values), Path("p.yaml"))[0]


def test_the_fitted_lines_are_rewritten_in_place():
    text = _rewrite({"strength": 2.5, "friction": 1e-5})
    lines = text.splitlines()
    assert lines[2] == "    strength: 2.5  # fitted by ftfof calibrate (reports/calibration.json)"
    assert lines[3].startswith("    friction: 1.0e-05  # fitted by ftfof calibrate")
    assert text.endswith("robot: m3f\n")
    assert yaml.safe_load(text)["surfaces"]["acrylic"] == {"strength": 2.5, "friction": 1e-5}


def test_a_fitted_value_without_a_line_is_a_params_error_naming_the_surface():
    with pytest.raises(ParamsError, match=r"surfaces.acrylic: has no key for \['rate_speed'\]"):
        _rewrite({"strength": 2.5, "rate_speed": 0.5})


def test_full_line_comments_under_a_fitted_key_are_kept():
    params = (
        "surfaces:\n  acrylic:\n    strength: 1.0  # a note\n"
        "    # why the next key has its value,\n    # on two lines\n    friction: 0.6\n"
    )
    text = edit_yaml(
        params, lambda doc: update_surface(doc, "acrylic", {"strength": 2.5}), Path("p.yaml")
    )[0]
    assert text.splitlines()[2:5] == [
        "    strength: 2.5  # fitted by ftfof calibrate (reports/calibration.json)",
        "    # why the next key has its value,",
        "    # on two lines",
    ]
    assert yaml.safe_load(text)["surfaces"]["acrylic"] == {"strength": 2.5, "friction": 0.6}


def test_a_fitted_backing_modulus_is_written_on_the_robots_foot():
    from stages.calibrate import update_backing

    params = (
        "robots:\n  m3f:\n    platform:\n      foot:\n        backing:\n"
        "          modulus: 1.0e6  # a guess\n          thickness: 0.001\n"
    )
    text = edit_yaml(
        params, lambda doc: update_backing(doc, "m3f", {"modulus": 2.5e6}), Path("p.yaml")
    )[0]
    assert "modulus: 2500000.0  # fitted by ftfof calibrate" in text
    backing = yaml.safe_load(text)["robots"]["m3f"]["platform"]["foot"]["backing"]
    assert backing == {"modulus": 2.5e6, "thickness": 0.001}
    grip = "robots:\n  m3f:\n    platform:\n      foot:\n        mass: 0.05\n"
    with pytest.raises(ParamsError, match=r"m3f.platform.foot.backing: has no key"):
        edit_yaml(grip, lambda doc: update_backing(doc, "m3f", {"modulus": 1.0}), Path("p.yaml"))
