"""`calibrate --write-params` refuses a params file it cannot rewrite with a one-line error."""

import pytest

from ftfof.errors import ParamsError
from stages.calibrate import update_surface

PARAMS = "surfaces:\n  acrylic:\n    strength: 1.0\nrobot: m3f\n"


def test_the_fitted_lines_are_rewritten_in_place():
    text = update_surface(PARAMS, "acrylic", {"strength": 2.5})
    assert text.splitlines()[2].startswith("    strength: 2.5  # fitted by ftfof calibrate")
    assert text.endswith("robot: m3f\n")


def test_a_fitted_value_without_a_line_is_a_params_error_naming_the_surface():
    with pytest.raises(
        ParamsError, match=r"surfaces.acrylic: no line to rewrite for \['friction'\]"
    ):
        update_surface(PARAMS, "acrylic", {"strength": 2.5, "friction": 0.5})
