"""fs1..fs7 and fsj on hand-made series (FTFOF §V.A)."""

from typing import get_args

import numpy as np
import pytest

from ftfof.config import Strategy
from ftfof.objectives import (
    STRATEGIES,
    Evidence,
    film_safety,
    fs1_max_detachment,
    fs2_mean_detachment,
    fs3_pre_pressure_error,
    fs4_mean_height,
    fs5_adhesion_path_length,
    fs6_bending,
    fs7_jitter,
    fsj_body_jitter,
    jitter_exceedance,
    strategy_values,
)


def test_fs1_is_the_peak_per_row():
    Fd = np.array([[0, 1, 3, 2], [5, 0, 0, 0]], dtype=float)
    np.testing.assert_array_equal(fs1_max_detachment(Fd), [3, 5])


def test_fs2_averages_up_to_complete_detachment():
    # peak 4 at i=2; first sample after it below 5 % of 4 (0.2) is i=4 -> mean of Fd[0..4]
    Fd = np.array([[1, 2, 4, 1, 0.1, 3, 3]], dtype=float)
    assert fs2_mean_detachment(Fd)[0] == pytest.approx((1 + 2 + 4 + 1 + 0.1) / 5)


def test_fs2_without_detachment_uses_the_whole_series():
    Fd = np.array([[1.0, 2.0, 3.0]])
    assert fs2_mean_detachment(Fd)[0] == pytest.approx(2.0)


def test_fs3_is_distance_of_peak_pre_pressure_from_a():
    Fp = np.array([[0, 4, 5.4, 5], [0, 4.5, 4.6, 0]])
    np.testing.assert_allclose(fs3_pre_pressure_error(Fp, 5.0), [0.4, 0.4])


def test_fs4_mean_height():
    pos = np.stack([np.zeros(5), np.array([0, 1, 2, 1, 0.0])], axis=-1)[None]
    assert fs4_mean_height(pos)[0] == pytest.approx(0.8)


def test_fs5_is_the_adhesion_path_length():
    t = np.linspace(0, 1, 1001)
    vel = np.zeros((1, t.size, 2))
    vel[0, :, 0] = 3.0  # 3 m/s along x
    vel[0, :, 1] = 4.0  # 4 m/s along z -> speed 5
    assert fs5_adhesion_path_length(vel, t, 0.5, 1.0)[0] == pytest.approx(2.5)


def test_fs6_is_zero_on_a_smooth_arc():
    a = np.linspace(0, np.pi, 200)
    arc = np.stack([np.cos(a), np.sin(a)], axis=-1)[None]
    assert fs6_bending(arc, 1e-9)[0] == 0.0


def test_fs6_is_positive_on_a_zig_zag():
    zig = np.array([[0, 0], [1, 0], [0, 0.2], [1, 0.4]], dtype=float)[None]
    # turns of 180 - atan(0.2) and 180 - 2 atan(0.2) degrees, each counted above 90
    expected = (np.pi / 2 - np.arctan(0.2)) + (np.pi / 2 - 2 * np.arctan(0.2))
    assert fs6_bending(zig, 1e-9)[0] == pytest.approx(expected)


def test_fs6_counts_a_reversal_through_a_standstill():
    """The tiny displacements at the turning point are skipped, the reversal is not."""
    x = np.concatenate([np.linspace(0, 1, 50), np.full(3, 1.0), np.linspace(1, 0, 50)])
    path = np.stack([x, np.zeros_like(x)], axis=-1)[None]
    assert fs6_bending(path, 1e-9)[0] == pytest.approx(np.pi / 2)


def test_fs6_is_vectorised_over_the_population():
    a = np.linspace(0, np.pi, 50)
    arc = np.stack([np.cos(a), np.sin(a)], axis=-1)
    zig = np.tile(np.array([[0, 0], [1, 0.0]]), (25, 1))
    out = fs6_bending(np.stack([arc, zig]), 1e-9)
    assert out[0] == 0 and out[1] > 0


def test_fs7_exceedance_is_zero_for_a_smooth_force_and_positive_for_a_snap():
    t = np.linspace(0, 1, 500)
    smooth = np.sin(np.pi * t)[None]
    snap = np.where(t < 0.5, t, 0.0)[None]  # force released at once
    assert fs7_jitter(np.cumsum(jitter_exceedance(smooth, t[1] - t[0]), axis=-1))[
        0
    ] == pytest.approx(0.0, abs=1e-9)
    assert fs7_jitter(np.cumsum(jitter_exceedance(snap, t[1] - t[0]), axis=-1))[0] > 1.0


def test_fs7_of_a_constant_series_is_zero():
    assert fs7_jitter(np.cumsum(jitter_exceedance(np.ones((1, 50)), 0.01), axis=-1))[0] == 0.0


def test_fsj_is_the_peak_body_acceleration_and_film_safety_the_bend_margin():
    acc = np.array([[1.0, 9.0, 2.0], [3.0, 3.0, 3.0]])
    np.testing.assert_array_equal(fsj_body_jitter(acc), [9.0, 3.0])
    curvature = np.array([[50.0, 200.0], [100.0, 150.0]])  # 1/m: radii 5 mm, 6.7 mm
    g = film_safety(curvature, 0.006)
    assert g[0] == pytest.approx(0.2) and g[1] < 0


def _evidence(pop: int = 3) -> Evidence:
    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 1.0, 51)
    position = np.cumsum(rng.random((pop, t.size, 2)), axis=1) * 1e-3
    series = {k: rng.random((pop, 40)) for k in ("pull", "Fd", "jitter", "body_acc")}
    return Evidence(
        series={**series, "Fp": rng.random((pop, 40)) * 6},
        dt=0.01,
        position=position,
        velocity=np.gradient(position, t, axis=1),
        t=t,
        adhesion=(0.6, 1.0),
        pre_pressure=5.0,
    )


def test_strategy_values_stack_the_named_functions_in_the_given_order():
    e = _evidence()
    values = strategy_values(["fs3", "fs1", "fs7", "fs5", "fsj", "fs1_normal"], e)
    assert values.shape == (3, 6)
    np.testing.assert_array_equal(values[:, 0], fs3_pre_pressure_error(e["Fp"], 5.0))
    np.testing.assert_array_equal(values[:, 1], fs1_max_detachment(e["pull"]))
    np.testing.assert_array_equal(values[:, 2], e["jitter"].max(axis=1))
    np.testing.assert_array_equal(values[:, 3], fs5_adhesion_path_length(e.velocity, e.t, 0.6, 1.0))
    np.testing.assert_array_equal(values[:, 4], e["body_acc"].max(axis=1))
    np.testing.assert_array_equal(values[:, 5], fs1_max_detachment(e["Fd"]))
    assert {f"fs{i}" for i in range(1, 8)} | {"fsj"} <= set(STRATEGIES)


def test_a_strategy_without_its_series_is_named():
    e = _evidence()
    with pytest.raises(KeyError, match="curvature"):
        e["curvature"]


def test_unknown_strategy_is_named():
    with pytest.raises(ValueError, match="fs9"):
        strategy_values(["fs1", "fs9"], _evidence())


def test_every_strategy_name_params_allow_has_a_function():
    assert set(STRATEGIES) == set(get_args(Strategy))
