"""Figures as matplotlib objects (the stages save them); Agg backend, no display needed."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure


def sample_figure(channels: Mapping[str, np.ndarray], title: str) -> Figure:
    """One acquisition: foot path, sensor forces, body jitter and intact bonds."""
    c = channels
    t = c["t"]
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), constrained_layout=True)
    ax = axes[0, 0]
    ax.plot(c["x_cmd"] * 1e3, c["z_cmd"] * 1e3, label="commanded")
    ax.plot(c["x_foot"] * 1e3, c["z_foot"] * 1e3, "--", label="actual ankle")
    ax.set(xlabel="x along the wall [mm]", ylabel="z from the wall [mm]", title="foot path")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend()
    ax = axes[0, 1]
    ax.plot(t, c["Fd"], label="detachment Fd")
    ax.plot(t, c["Fp"], label="pre-pressure Fp")
    ax.plot(t, c["Fx"], lw=0.8, label="tangential Fx")
    ax.set(xlabel="t from trajectory start [s]", ylabel="force [N]", title="force sensor")
    ax.legend()
    ax = axes[1, 0]
    ax.plot(t, c["body_acc"])
    ax.set(xlabel="t [s]", ylabel="|a| [m/s²]", title="body IMU (jitter)")
    ax = axes[1, 1]
    ax.step(t, c["bonds"], where="post", label="intact bonds")
    ax.step(t, c["switch"] * c["bonds"].max(), where="post", label="switch (detached)")
    ax.set(xlabel="t [s]", ylabel="count", title="adhesive interface")
    ax.legend()
    fig.suptitle(title)
    return fig
