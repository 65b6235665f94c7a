"""The climb's figures draw what the channels say, from synthetic channels."""

from __future__ import annotations

import numpy as np

from ftfof.report.climb_figure import climb_figure, climb_filmstrip


def _channels(n: int = 50) -> dict[str, np.ndarray]:
    t = np.linspace(0.0, 1.0, n)
    theta = np.tile([1.0, -2.0, 1.0], 4)
    return {
        "t": t,
        "body": np.column_stack([0.01 * t, np.zeros(n), np.zeros(n)]),
        "body_plan": 0.01 * t,
        "foot": np.tile([0.1, 0.015], (n, 4)),
        "force": np.zeros((n, 8)),
        "bonds": np.full((n, 4), 41.0),
        "joints": np.tile(theta, (n, 1)),
    }


def test_the_filmstrip_draws_one_panel_per_frame_with_trunk_legs_and_pads():
    c = _channels()
    fig = climb_filmstrip(c, [0.0, 0.5, 1.0], np.array([0.1, 0.1, -0.1, -0.1]), 0.04,
                          (0.12, 0.12), 0.015, 0.05, "test")  # fmt: skip
    axes = [ax for ax in fig.axes if ax.get_title().startswith("t = ")]
    assert len(axes) == 3
    # wall line, trunk, and a chain and a pad per leg
    assert len(axes[0].lines) == 1 + 1 + 2 * 4
    trunk = axes[0].lines[1].get_ydata()
    assert sorted(trunk) == [-100.0, 100.0]  # mm: the hips 0.2 m apart, body at x = 0


def test_the_traces_shade_each_swing():
    c = _channels()
    imu = {"t": c["t"], "acc": np.abs(np.sin(10 * c["t"]))}
    fig = climb_figure(c, imu, [(0.1, 0.3), (0.5, 0.7)], "test")
    assert len(fig.axes) == 4
    assert all(len(ax.patches) == 2 for ax in fig.axes)
