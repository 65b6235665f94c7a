"""identify's figure: the Kalman estimate converging over a slip log."""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from ftfof.identify.estimate import Track


def convergence_figure(out: dict[str, Any], track: Track) -> Figure:
    """The Kalman estimate over the log, beside least squares and the truth where known."""
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(6, 5))
    for ax, name, values in (
        (axes[0], "mu", track.mu),
        (axes[1], "adhesion", track.adhesion),
    ):
        ax.plot(track.samples, values, label="Kalman estimate")
        ax.axhline(out[name]["least_squares"], ls=":", color="k", label="least squares")
        if out[name]["truth"] is not None:
            ax.axhline(out[name]["truth"], ls="--", color="g", label="truth")
        ax.set_ylabel("μ" if name == "mu" else "F_adh per pad, N")
    axes[0].legend()
    axes[1].set_xlabel("slip samples seen")
    fig.tight_layout()
    return fig
