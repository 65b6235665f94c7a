"""The ε study's pure parts: the sweep re-times one curve, the landing's rise rate, the seed's
trend read off the points, the command line's ε list."""

import numpy as np
import pytest

from ftfof.errors import ParamsError
from ftfof.study.eps import EpsPoint, landing_rate, parse_epsilons, swept, trend
from ftfof.trajectory.baselines import EpsBezier

POINTS = np.array([[0.0, 0.0], [0.01, 0.04], [0.05, 0.04], [0.06, 0.0]])


def test_the_sweep_keeps_the_curve_and_only_re_times_it():
    base = EpsBezier(POINTS, 2.0, 0.5)
    plain, steep = swept(base, [0.0, 8.0])
    assert plain.eps == 0.0 and steep.eps == 8.0
    t = np.linspace(0.0, 0.5, 101)
    a, b = plain.sample(t), steep.sample(t)
    np.testing.assert_allclose(a.position[0, [0, -1]], b.position[0, [0, -1]], atol=1e-12)
    np.testing.assert_allclose(a.position[0, 50], b.position[0, 50], atol=1e-12)  # m(1/2) = 1/2
    # ε = 0 is the plain Bezier: the foot lands at the curve's own speed; ε = 8 nearly stops it
    end = (np.linalg.norm(a.velocity[0, -1]), np.linalg.norm(b.velocity[0, -1]))
    assert end[0] > 10 * end[1] > 0


def test_the_landing_rate_is_the_steepest_rise_inside_the_window():
    t = np.arange(0.0, 0.01, 0.001)
    Fp = np.array([0, 0, 1, 3, 4, 4, 0, 9, 9, 9], dtype=float)
    landed = t < 0.006  # the jump to 9 N comes after the window
    assert landing_rate(t, Fp, landed) == pytest.approx(2000.0)
    assert landing_rate(t, Fp, np.ones_like(landed)) == pytest.approx(9000.0)


def _points(peaks: dict[float, float]) -> list[EpsPoint]:
    return [EpsPoint(e, p, 0.0, 0.0, 0.0, 0.0, 0.0) for e, p in peaks.items()]


def test_the_trend_is_the_seeds_only_when_it_falls_to_4_and_stays_within_10_percent():
    falls = {0.0: 12.0, 1.0: 11.0, 2.0: 9.0, 4.0: 7.5, 8.0: 7.0}
    good = trend(_points(falls))
    assert good["falls_up_to_4"] and good["flat_4_to_8"] and good["agrees_with_seed"]
    assert good["change_4_to_8"] == pytest.approx(-0.5 / 7.5)
    rises = trend(_points({**falls, 1.0: 12.5}))
    assert rises["falls_up_to_4"] is False and rises["agrees_with_seed"] is False
    drops_on = trend(_points({**falls, 8.0: 6.0}))
    assert drops_on["flat_4_to_8"] is False and drops_on["agrees_with_seed"] is False


def test_a_sweep_without_4_or_8_cannot_say():
    missing = trend(_points({0.0: 12.0, 2.0: 9.0}))
    assert missing["falls_up_to_4"] is None and missing["change_4_to_8"] is None
    assert missing["agrees_with_seed"] is None


def test_the_epsilons_come_sorted_and_bad_lists_are_refused():
    assert parse_epsilons("8,0,0.5") == [0.0, 0.5, 8.0]
    for bad in ("1,x", "-1,2", "1,1", "inf"):
        with pytest.raises(ParamsError, match="--epsilons"):
            parse_epsilons(bad)
