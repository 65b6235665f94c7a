"""The slip figures of a climb's channels, and the controller option's refusal."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

from ftfof.climb.metrics import slip_totals
from stages.cli import app
from tests.conftest import ROOT


def _channels(velocity: np.ndarray) -> dict[str, np.ndarray]:
    return {"t": np.linspace(0.0, 1.0, len(velocity)), "slip_velocity": velocity}


def test_pads_that_never_move_slip_nothing():
    totals = slip_totals(_channels(np.zeros((11, 4))))
    assert totals.summary() == {"slip_distance": 0.0, "slip_path": 0.0, "max_slip_velocity": 0.0}


def test_the_slip_distance_is_how_far_a_pad_got_from_where_its_stance_began():
    v = np.zeros((11, 4))
    v[1:, 1] = -0.002  # FR slides down the wall at 2 mm/s (from its first record on)
    v[5, 3] = 0.01  # HR jolts up once
    totals = slip_totals(_channels(v))
    assert totals.distance[1] == pytest.approx(0.0018)  # 9 intervals of 0.1 s
    assert totals.peak[3] == 0.01 and totals.distance[0] == 0.0
    assert totals.by_foot()["FR"]["slip_distance"] == pytest.approx(0.0018)


def test_ringing_adds_to_the_path_but_not_to_the_distance():
    t = np.linspace(0.0, 1.0, 1001)
    v = np.zeros((t.size, 4))
    v[:, 2] = 0.05 * np.sin(2 * np.pi * 50 * t) + 1e-9  # HL's film rings at 50 Hz, +-50 mm/s
    totals = slip_totals({"t": t, "slip_velocity": v})
    assert totals.path[2] == pytest.approx(0.1 / np.pi, rel=0.02)  # 50 cycles of 2 * 0.05 / pi / 50
    assert totals.distance[2] < 0.05 / (np.pi * 50) + 1e-6  # one half-swing: 0.32 mm


def test_each_stance_counts_its_own_excursion_and_a_slide_back_cancels():
    v = np.zeros((21, 4))
    v[1:5, 0] = 0.01  # FL slides up for 3 intervals, then lifts (v = 0 off the stance)
    v[6:11, 0] = -0.01  # a new stance: down for 4 intervals ...
    v[11:16, 0] = 0.01  # ... and back up to where it began
    totals = slip_totals(_channels(v))
    interval = 1.0 / 20
    assert totals.distance[0] == pytest.approx((3 + 4) * 0.01 * interval)


def test_an_unknown_controller_is_refused_naming_the_option(tmp_path):
    args = ["climb", "--params", str(ROOT / "params.yaml"), "--baseline", "polynomial"]
    result = CliRunner().invoke(app, [*args, "--controller", "fast", "--out-dir", str(tmp_path)])
    assert result.exit_code == 2 and "--controller" in result.stderr
    assert not any(tmp_path.iterdir())
