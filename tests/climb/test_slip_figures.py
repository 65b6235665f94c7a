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
    assert totals.summary() == {"slip_distance": 0.0, "max_slip_velocity": 0.0}


def test_the_slip_distance_is_the_speed_integrated_whichever_way_it_slides():
    v = np.zeros((11, 4))
    v[:, 1] = -0.002  # FR slides down the wall at 2 mm/s for a second
    v[5, 3] = 0.01  # HR jolts up once
    totals = slip_totals(_channels(v))
    assert totals.distance[1] == pytest.approx(0.002)
    assert totals.peak[3] == 0.01 and totals.distance[0] == 0.0
    assert totals.by_foot()["FR"]["slip_distance"] == pytest.approx(0.002)


def test_an_unknown_controller_is_refused_naming_the_option(tmp_path):
    args = ["climb", "--params", str(ROOT / "params.yaml"), "--baseline", "polynomial"]
    result = CliRunner().invoke(app, [*args, "--controller", "fast", "--out-dir", str(tmp_path)])
    assert result.exit_code == 2 and "--controller" in result.stderr
    assert not any(tmp_path.iterdir())
