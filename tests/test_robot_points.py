"""Control points typed on a command line: parsed in metres, checked against the robot's rules."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.errors import ParamsError
from ftfof.robot import check_points, parse_points


def test_parse_points_in_millimetres_and_its_errors():
    text = ",".join(str(v) for v in range(12))
    np.testing.assert_allclose(parse_points(text, "mm"), np.arange(12) * 1e-3)
    with pytest.raises(ParamsError, match="must be m or mm"):
        parse_points(text, "cm")
    with pytest.raises(ParamsError, match="needs 12 values"):
        parse_points("1,2", "m")
    with pytest.raises(ParamsError, match="12 comma-separated numbers"):
        parse_points("a," * 11 + "b", "m")


def test_points_a_thousand_times_off_are_refused_with_the_likely_unit(m3f):
    reach = float(np.max(m3f.limits.position))
    X = np.full(12, 0.5 * reach)
    with pytest.raises(ParamsError, match="look like millimetres"):
        check_points(X * 1e3, "m", m3f, allow_infeasible=True)
    with pytest.raises(ParamsError, match="look like metres"):
        check_points(X * 1e-3, "mm", m3f, allow_infeasible=True)  # metres typed as mm


def test_broken_rules_are_refused_unless_allowed(m3f):
    X = np.zeros(12)  # every control point at the start: no lift, no path
    failed = check_points(X, "m", m3f, allow_infeasible=True)
    assert failed
    with pytest.raises(ParamsError, match="cannot run them"):
        check_points(X, "m", m3f, allow_infeasible=False)
