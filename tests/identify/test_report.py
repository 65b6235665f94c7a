"""identify's report and surface preset from estimates in memory (no log, no simulator)."""

from __future__ import annotations

import numpy as np
import pytest

from ftfof.identify.estimate import Estimate, Track
from ftfof.identify.fit import preset_block, report

TRACK = Track(np.array([15, 30]), np.array([0.5, 0.46]), np.array([28.0, 30.5]))


def test_the_report_sets_the_estimate_beside_least_squares_and_the_truth():
    out = report("glass", "simulated slip test", Estimate(0.45, 31.0), TRACK, Estimate(0.45, 30))
    assert out["slip_samples"] == 30
    assert out["mu"] == {"estimate": 0.46, "truth": 0.45, "least_squares": 0.45}
    assert out["adhesion"]["estimate"] == 30.5
    assert report("glass", "log.csv", Estimate(0.4, 1.0), TRACK, None)["mu"]["truth"] is None


def test_the_preset_takes_the_friction_and_the_strength_from_the_shear(params):
    surface = params.surfaces["glass"]
    block = preset_block(surface, "log.csv", 0.456789, 2.0e4)
    assert block["friction"] == 0.4568
    assert block["strength"] == pytest.approx(2.0e4 / surface.shear_capacity_ratio, abs=0.1)
    assert block["note"].endswith("(log.csv).")
    calibrated = preset_block(surface, "log.csv", 0.45, 2.0e4, pull_off=1.0e4)
    assert (calibrated["strength"], calibrated["shear_capacity_ratio"]) == (1.0e4, 2.0)
