"""`ftfof calibrate --fix / --bound`: what the fit holds and where, or one error naming the key."""

import pytest

from ftfof.errors import DataError, ParamsError
from ftfof.identify.calibration import fit_bounds, fitted_strength, parse_bounds, parse_fixes


def test_fixes_and_bounds_parse_to_values_in_si():
    assert parse_fixes(["fracture_energy=60"]) == {"fracture_energy": 60.0}
    assert parse_bounds(["strength=1e4:1e5"]) == {"strength": (1e4, 1e5)}


def test_a_fixed_value_leaves_the_fit_and_a_bound_replaces_the_default_range():
    bounds = fit_bounds("preload_pressure", {"fracture_energy": 60.0}, {"strength": (1e4, 1e5)})
    assert bounds == {"strength": (1e4, 1e5), "preload_pressure": (2e2, 5e4)}
    assert fit_bounds("preload_pressure", {"preload_pressure": 1e4}, {}) == {
        "strength": (2e3, 5e5),
        "fracture_energy": (1.0, 5e3),
    }


@pytest.mark.parametrize(
    ("fixes", "bounds", "third", "message"),
    [
        (["stregth=1"], [], "none", "--fix stregth: is not a parameter the fit knows"),
        (["strength"], [], "none", "--fix: 'strength' is not key=value"),
        (["strength=-3"], [], "none", "--fix strength: must be a positive number"),
        ([], ["strength=1e5:1e4"], "none", "--bound strength: needs lo < hi"),
        ([], ["strength=1e4"], "none", "--bound strength: '1e4' is not lo:hi"),
        ([], ["strength=a:1e4"], "none", "--bound strength: 'a' is not a number"),
        ([], ["friction=0.2:0.9"], "none", "--bound friction: is not fitted"),
        (["strength=3e4"], ["strength=1e4:1e5"], "none", "--bound strength: is also fixed"),
        (["strength=3e4", "fracture_energy=60"], [], "none", "--fix: holds every parameter"),
        ([], [], "colour", "--third: cannot fit 'colour'"),
        (["strength=3e4", "strength=4e4"], [], "none", "--fix strength: is given twice"),
        ([], ["strength=1:2", "strength=1:3"], "none", "--bound strength: is given twice"),
    ],
)
def test_a_bad_key_or_range_is_one_error_naming_it(fixes, bounds, third, message):
    with pytest.raises(ParamsError) as err:
        fit_bounds(third, parse_fixes(fixes), parse_bounds(bounds))
    assert str(err.value).startswith(message)
    assert "\n" not in str(err.value)


def test_the_strength_is_the_fitted_or_held_one_of_the_surface_it_calibrates():
    report = {"surface": "glass", "fixed": {"strength": 2.0}, "values": {"strength": 3.0}}
    assert fitted_strength(report, "glass", "r.json") == 3.0
    assert fitted_strength({**report, "values": {}}, "glass", "r.json") == 2.0
    with pytest.raises(DataError, match=r"r\.json: calibrates surface 'glass', not 'ice'"):
        fitted_strength(report, "ice", "r.json")
    with pytest.raises(DataError, match="has no strength"):
        fitted_strength({**report, "fixed": {}, "values": {}}, "glass", "r.json")
    with pytest.raises(DataError, match="not a calibration report"):
        fitted_strength([1], "glass", "r.json")
