"""Figures of the evaluation report: FTFOF Fig. 11 (paths), 12 (forces), 14 (jitter), fidelity,
and the choice among the simulated candidates."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from ftfof.evaluate.choice import CHOSEN, Candidate

OPTIMUM_STYLE = {"color": "crimson", "lw": 2.2, "zorder": 5}
# the visits that removed candidates: tab10 without its red, which marks the chosen one
REMOVED_COLOURS = (
    "tab:blue",
    "tab:orange",
    "tab:green",
    "tab:purple",
    "tab:brown",
    "tab:pink",
    "tab:gray",
    "tab:olive",
    "tab:cyan",
)


def _style(name: str, optimum: str) -> dict:
    return OPTIMUM_STYLE if name == optimum else {"lw": 1.2, "alpha": 0.85}


def paths_figure(channels: Mapping[str, Mapping[str, np.ndarray]], optimum: str) -> Figure:
    """Commanded foot paths overlaid (Fig. 11), millimetres in the trajectory frame."""
    fig, ax = plt.subplots(figsize=(7.5, 4.2), constrained_layout=True)
    for name, c in channels.items():
        ax.plot(1e3 * c["x_cmd"], 1e3 * c["z_cmd"], label=name, **_style(name, optimum))
    ax.set(xlabel="x along the wall [mm]", ylabel="z from the wall [mm]", title="foot trajectories")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8)
    return fig


def forces_figure(channels: Mapping[str, Mapping[str, np.ndarray]], optimum: str) -> Figure:
    """Detachment force and pre-pressure against time for every trajectory (Fig. 12)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 3.8), constrained_layout=True, sharex=True)
    for name, c in channels.items():
        ax1.plot(c["t"], c["Fd"], label=name, **_style(name, optimum))
        ax2.plot(c["t"], c["Fp"], label=name, **_style(name, optimum))
    ax1.set(xlabel="t from trajectory start [s]", ylabel="Fd [N]", title="detachment force")
    ax2.set(xlabel="t from trajectory start [s]", ylabel="Fp [N]", title="pre-pressure")
    ax1.legend(fontsize=8)
    return fig


def jitter_figure(channels: Mapping[str, Mapping[str, np.ndarray]], optimum: str) -> Figure:
    """Body IMU acceleration magnitude for every trajectory (Fig. 14)."""
    fig, ax = plt.subplots(figsize=(11, 3.4), constrained_layout=True)
    for name, c in channels.items():
        ax.plot(c["t"], c["body_acc"], label=name, **_style(name, optimum))
    ax.set(xlabel="t from trajectory start [s]", ylabel="|a| [m/s²]", title="body jitter (IMU)")
    ax.legend(fontsize=8)
    return fig


def fidelity_figure(
    names: Sequence[str], predicted: np.ndarray, simulated: np.ndarray, optimum: int
) -> Figure:
    """Predicted against simulated objective per front point; the optimum in red."""
    k = len(names)
    fig, axes = plt.subplots(1, k, figsize=(3.3 * k, 3.3), constrained_layout=True, squeeze=False)
    for j, (ax, name) in enumerate(zip(axes[0], names, strict=True)):
        p, s = predicted[:, j], simulated[:, j]
        low, high = float(min(p.min(), s.min())), float(max(p.max(), s.max()))
        pad = 0.05 * (high - low) or 0.05 * abs(high) or 1.0
        ax.plot([low - pad, high + pad], [low - pad, high + pad], color="0.6", lw=0.8)
        ax.scatter(s, p, s=14, label="front")
        ax.scatter(s[optimum], p[optimum], s=40, color="crimson", label="optimum", zorder=5)
        ax.set(xlabel=f"simulated {name}", ylabel=f"predicted {name}")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle("surrogate fidelity")
    return fig


def choice_figure(
    candidates: Sequence[Candidate],
    axes_names: tuple[str, str],
    references: Mapping[str, tuple[float, float]],
) -> Figure:
    """The candidates RHS chose among on its first two priorities (simulated means, ± one
    standard deviation over their runs), coloured by the visit that removed them; the chosen one
    as a star and the ``references`` (nominal runs of named trajectories) as crosses."""
    x_name, y_name = axes_names
    fig, ax = plt.subplots(figsize=(7.5, 4.6), constrained_layout=True)
    groups: dict[str, list[Candidate]] = {}
    for c in sorted(candidates, key=lambda c: c.visit):
        groups.setdefault(c.removed_by, []).append(c)
    others = iter(REMOVED_COLOURS)
    for removed_by, members in groups.items():
        x = np.array([c.mean[x_name] for c in members])
        y = np.array([c.mean[y_name] for c in members])
        xerr = np.array([c.spread.get(x_name, 0.0) for c in members])
        yerr = np.array([c.spread.get(y_name, 0.0) for c in members])
        if removed_by == CHOSEN:
            style = {"color": "crimson", "marker": "*", "ms": 16, "zorder": 6, "label": "chosen"}
        else:
            style = {"color": next(others), "marker": "o", "ms": 6, "alpha": 0.85}
            style["label"] = f"removed by {removed_by}"
        ax.errorbar(x, y, xerr=xerr, yerr=yerr, ls="none", elinewidth=0.8, capsize=2, **style)
    for name, (x, y) in references.items():
        ax.plot(x, y, marker="X", ms=10, ls="none", color="0.25")
        ax.annotate(name, (x, y), textcoords="offset points", xytext=(6, 4), fontsize=8)
    ax.set(
        xlabel=f"simulated {x_name} (mean over the runs)",
        ylabel=f"simulated {y_name} (mean over the runs)",
        title="the candidates RHS chose among, as simulated",
    )
    ax.legend(fontsize=8)
    return fig
