"""The refinement figure: surrogate fidelity on each round's re-simulated points, round by round."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure


def refine_figure(rounds: Sequence[dict], objectives: Sequence[str]) -> Figure:
    """Spearman's rho and the median relative error per objective against round, the fraction of
    the round's points the simulator passes, and the chosen optimum's relative error on the
    first-priority objective (as in reports/refine.json)."""
    fig, (rho_ax, err_ax) = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    if not rounds:
        for ax in (rho_ax, err_ax):
            ax.text(0.5, 0.5, "no refinement rounds (refine.rounds: 0)", ha="center", va="center")
            ax.set_axis_off()
        return fig
    k = [r["round"] for r in rounds]
    for name in objectives:
        fid = [r["fidelity"][name] for r in rounds]
        rho_ax.plot(k, [f["spearman"] for f in fid], marker="o", label=name)
        err_ax.plot(k, [f["median_relative_error"] for f in fid], marker="o", label=name)
    first = objectives[0]
    optimum = [
        abs(r["optimum"]["predicted"][first] - r["optimum"]["simulated"][first])
        / max(abs(r["optimum"]["simulated"][first]), 1e-12)
        for r in rounds
    ]
    err_ax.plot(k, optimum, color="crimson", ls="--", marker="s", label=f"optimum {first}")
    clean = [r["clean_fraction"] for r in rounds]
    rho_ax.plot(k, clean, color="black", ls=":", marker="x", label="clean fraction")
    rho_ax.set(xlabel="round", ylabel="Spearman ρ", title="rank fidelity on the round's points")
    err_ax.set(xlabel="round", ylabel="relative error", title="median relative error")
    if np.all(np.isfinite(optimum)) and min(optimum) > 0:
        err_ax.set_yscale("log")
    for ax in (rho_ax, err_ax):
        ax.set_xticks(k)
    rho_ax.legend(fontsize=8)
    err_ax.legend(fontsize=8)
    return fig
