"""The climb's traces (as FTFOF Fig. 14 shows its IMU): jitter, body path, pad forces, bonds."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import NDArray

from ftfof.config import LEG_NAMES

Array = NDArray[np.float64]


def climb_figure(
    channels: dict[str, Array], imu: dict[str, Array], swings: list[tuple[float, float]], title: str
) -> Figure:
    """Four panels over the climb's time; each swing (lift-off to landing) shaded."""
    c = channels
    t = c["t"]
    fig, axes = plt.subplots(4, 1, figsize=(11, 10), sharex=True, constrained_layout=True)
    for ax in axes:
        for start, end in swings:
            ax.axvspan(start, end, color="0.92", lw=0)
    axes[0].plot(imu["t"], imu["acc"], lw=0.7)
    axes[0].set(ylabel="IMU |a| [m/s²]", title=title)
    axes[1].plot(t, 1e3 * c["body"][:, 0], label="body x")
    axes[1].plot(t, 1e3 * c["body_plan"], "--", label="plan")
    axes[1].plot(t, 1e3 * c["body"][:, 1], label="body z")
    axes[1].set(ylabel="body [mm]")
    axes[1].legend(loc="upper left")
    for leg, name in enumerate(LEG_NAMES):
        axes[2].plot(t, c["force"][:, 2 * leg + 1], lw=0.8, label=name)
        axes[3].plot(t, c["bonds"][:, leg], lw=0.8, label=name)
    axes[2].set(ylabel="pad pull on the wall Fz [N]")
    axes[2].legend(loc="upper left", ncol=4)
    axes[3].set(ylabel="bonds holding", xlabel="t [s]")
    return fig
