"""Target series: each on its window, binned so the objectives read the full-rate values."""

from typing import get_args

import numpy as np
import pytest

from ftfof.config import Target
from ftfof.data import targets
from ftfof.objectives import JITTER_SIGMAS, jitter_exceedance
from tests.data.fake import SWITCH, fake_channels, film_clearance, film_curvature

T3, HOLD, N = 1.0, 0.1, 100


def test_bin_max_keeps_a_narrow_peak_that_interpolation_would_miss():
    t = np.arange(0.0, 1.0, 1e-3)
    f = np.where(np.abs(t - 0.3004) < 1e-3, 7.0, 0.1)
    assert targets.bin_max(t, f, 0.9, 0.1, 32).max() == 7.0
    assert np.interp(targets.time_base(0.9, 0.1, 32), t, f).max() < 7.0


def test_pull_is_the_resultant_while_the_pad_holds():
    ch = fake_channels(4.0)
    s = targets.binned(ch, T3, HOLD, N)
    assert s["pull"].max() == pytest.approx(4.0 * np.hypot(1.0, 0.4), rel=1e-6)
    assert s["Fd"].max() == pytest.approx(4.0, rel=1e-6)
    after = targets.time_base(T3, HOLD, N) > 0.15 + 0.011  # bonds all broken at 0.15 s
    assert np.all(s["pull"][after] == 0) and np.all(s["Fd"][after] == 0)


def test_pre_pressure_is_the_landing_not_the_held_initial_press():
    ch = fake_channels(4.0)
    t = ch["t"]
    ch["Fz_pad"] = np.where(t < 0.03, -5.0, ch["Fz_pad"])  # the press still held after t = 0
    ch["Fz_pad"] = np.where(t > 0.9, -4.2 * np.exp(-((t - 1.0) ** 2) / 1e-3), ch["Fz_pad"])
    s = targets.binned(ch, T3, HOLD, N)
    assert s["Fp"].max() == pytest.approx(4.2, rel=1e-3)
    assert np.all(s["Fp"][targets.time_base(T3, HOLD, N) < SWITCH] == 0)


def test_jitter_runs_up_to_eq16_on_the_detachment_window_at_the_full_rate():
    ch = fake_channels(4.0)
    t = ch["t"]
    ch["Fz_pad"] = ch["Fz_pad"] + 0.3 * ((t > 0.05) & (t < 0.052))  # a step: a jerk in F''
    s = targets.binned(ch, T3, HOLD, N)
    window = (t >= 0) & (t <= SWITCH + targets.JITTER_TAIL)
    pull = np.hypot(ch["Fx_pad"], np.maximum(ch["Fz_pad"], 0))[window]
    expected = jitter_exceedance(pull, 1e-3, JITTER_SIGMAS).sum()
    assert expected > 1.0
    assert s["jitter"].max() == pytest.approx(expected, rel=1e-9)
    assert np.all(np.diff(s["jitter"]) >= 0)  # a running total
    assert s["jitter"][targets.time_base(T3, HOLD, N) < 0.04].max() == 0  # none before the jerk
    after = s["jitter"][targets.time_base(T3, HOLD, N) > SWITCH + 0.03]
    np.testing.assert_allclose(after, expected, rtol=1e-9)  # held after the window


def test_a_coarse_record_supplies_no_jitter():
    ch = {k: v[::3] for k, v in fake_channels(4.0).items()}  # 3 ms
    assert np.isnan(targets.binned(ch, T3, HOLD, N)["jitter"]).all()


def test_body_jitter_counts_the_release_not_the_landing():
    ch = fake_channels(4.0)
    t = ch["t"]
    ch["body_acc"] = ch["body_acc"] + 100.0 * (np.abs(t - 1.0) < 0.005)  # landing impact
    s = targets.binned(ch, T3, HOLD, N)
    assert s["body_acc"].max() == pytest.approx(2.0 + 12.0, rel=1e-3)  # ring at 0.15 s
    assert np.all(s["body_acc"][targets.time_base(T3, HOLD, N) > SWITCH + 0.06] == 0)


def test_film_curvature_is_binned_by_maximum_and_masked_where_unseen():
    ch = fake_channels(3.0, with_film=False)
    assert np.isnan(targets.binned(ch, T3, HOLD, N)["curvature"]).all()
    ch["film_curvature"] = film_curvature(ch["t"], 3.0)
    assert targets.binned(ch, T3, HOLD, N)["curvature"].max() == pytest.approx(100.0, rel=1e-6)


def test_pad_clearance_is_binned_by_maximum_and_masked_where_unseen():
    ch = fake_channels(3.0, with_film=False)
    assert np.isnan(targets.binned(ch, T3, HOLD, N)["clearance"]).all()
    ch["film_clearance"] = film_clearance(ch["t"])
    assert targets.binned(ch, T3, HOLD, N)["clearance"].max() == pytest.approx(0.05, rel=1e-4)


def test_a_pad_that_never_lets_go_pulls_to_the_end_and_never_lands():
    """The switch never trips: the pad drags and re-bonds while the foot moves. Its pull counts
    to the end (the landing drag too) and it has no landing press, as the acquisition says."""
    ch = fake_channels(4.0)
    t = ch["t"]
    ch["switch"] = np.zeros_like(t)
    ch["bonds"] = np.where(t > 0.9, 5.0, ch["bonds"])  # re-bonded at the landing, still moving
    ch["Fx_pad"] = np.where(t > 0.9, 30.0, ch["Fx_pad"])  # dragged along the wall
    s = targets.binned(ch, T3, HOLD, N)
    assert s["pull"].max() == pytest.approx(30.0, rel=1e-3)
    assert np.all(s["Fp"] == 0)


def test_a_force_log_supplies_the_forces_only():
    ch = fake_channels(4.0)
    nan = np.full_like(ch["t"], np.nan)
    ch.update(
        Fx_pad=nan, body_acc=nan, bonds=nan, switch=nan, film_curvature=nan, film_clearance=nan
    )
    s = targets.binned(ch, T3, HOLD, N)
    assert s["Fd"].max() == pytest.approx(4.0, rel=1e-6)  # the tension it measured
    assert np.isnan(s["pull"]).all() and np.isnan(s["jitter"]).all()  # no resultant: masked
    assert np.isnan(s["body_acc"]).all() and np.isnan(s["curvature"]).all()
    assert np.isnan(s["clearance"]).all()
    assert s["Fp"].max() == pytest.approx(5.0, rel=1e-3)  # detachment by eq. 11's 5 % rule


def test_retouch_counts_bonds_formed_again_between_the_switch_and_the_landing_segment():
    ch = fake_channels(4.0)
    t = ch["t"]
    assert np.isnan(targets.binned(ch, T3, HOLD, N)["retouch"]).all()  # no T2 given
    clean = targets.binned(ch, T3, HOLD, N, landing_start=0.6)["retouch"]
    assert np.all(clean == 0)  # the fake pad lets go (switch at 0.2 s) and lands at T3
    ch["bonds"] = np.where((t > SWITCH + 0.01) & (t < SWITCH + 0.06), 2.0, ch["bonds"])
    ch["bonds"] = np.where(t > 0.8, 20.0, ch["bonds"])  # the landing re-bonds: not a retouch
    s = targets.binned(ch, T3, HOLD, N, landing_start=0.6)["retouch"]
    assert s.max() == 2.0
    base = targets.time_base(T3, HOLD, N)
    assert np.all(s[base > SWITCH + 0.08] == 0) and np.all(s[base < SWITCH] == 0)


def test_a_pad_that_never_lets_go_counts_every_bond_it_holds_as_a_retouch():
    ch = fake_channels(4.0)
    t = ch["t"]
    ch["switch"] = np.zeros_like(t)
    ch["bonds"] = np.where(t > 0.1, 3.0, ch["bonds"])  # its tail stays on the wall
    s = targets.binned(ch, T3, HOLD, N, landing_start=0.6)["retouch"]
    assert s.max() == 20.0  # from t = 0: the whole pad, then its tail
    assert np.all(s[targets.time_base(T3, HOLD, N) > 0.6 + 0.0125] == 0)


def test_retouch_needs_the_switch_and_the_bonds():
    ch = fake_channels(4.0)
    nan = np.full_like(ch["t"], np.nan)
    assert np.isnan(targets.binned({**ch, "switch": nan}, T3, HOLD, N, 0.6)["retouch"]).all()
    assert np.isnan(targets.binned({**ch, "bonds": nan}, T3, HOLD, N, 0.6)["retouch"]).all()


def test_the_retouch_constraint_refuses_what_the_release_verdict_refuses():
    """The target and the simulator's verdict read the same window: a bond back on the wall
    between the switch and T2 fails both; one formed at the landing fails neither."""
    from ftfof.data.release import release_fault
    from ftfof.objectives import pad_retouch

    ch = fake_channels(4.0)
    t = ch["t"]
    landing = np.where(t > 0.8, 20.0, ch["bonds"])
    back = np.where((t > SWITCH + 0.01) & (t < SWITCH + 0.06), 1.0, landing)
    for bonds, refused in ((landing, False), (back, True)):
        record = {**ch, "bonds": bonds}
        g = pad_retouch(targets.binned(record, T3, HOLD, N, landing_start=0.6)["retouch"], 0.5)
        fault = release_fault(t, bonds, SWITCH, 0.05, 0.009, 0.6)
        assert (g > 0) == refused == fault.startswith("the pad touched the wall again")


def test_the_settings_name_every_target_in_order():
    assert get_args(Target) == targets.TARGETS
