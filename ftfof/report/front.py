"""Pareto-front figures (FTFOF Fig. 10): star and parallel coordinates with pymoo's plots, and
the search's convergence. Every figure highlights the trajectory RHS chose."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from pymoo.visualization.pcp import PCP
from pymoo.visualization.star_coordinate import StarCoordinate

FRONT_STYLE = {"color": "tab:blue", "alpha": 0.35}
CHOSEN_STYLE = {"color": "tab:red", "label": "RHS choice"}


def _bounds(F: np.ndarray) -> list[np.ndarray]:
    low, high = F.min(axis=0), F.max(axis=0)
    return [low, np.where(high > low, high, low + 1.0)]  # a constant column still gets an axis


def star_figure(F: np.ndarray, names: Sequence[str], chosen: int, title: str) -> Figure:
    """Each front member as a point in star coordinates (objectives normalised to the front)."""
    plot = StarCoordinate(
        labels=list(names), bounds=_bounds(F), title=title, figsize=(6.5, 6.5), legend=True
    )
    plot.add(F, s=14, **FRONT_STYLE, label="Pareto front")
    plot.add(F[chosen : chosen + 1], s=90, marker="*", **CHOSEN_STYLE)
    plot.do()
    return plot.fig


def pcp_figure(F: np.ndarray, names: Sequence[str], chosen: int, title: str) -> Figure:
    """One polyline per front member across the objectives, the choice drawn on top."""
    plot = PCP(
        labels=list(names),
        bounds=_bounds(F),
        title=(title, {"pad": 28}),
        figsize=(9, 4.5),
        legend=True,
    )
    plot.add(F, linewidth=0.8, **FRONT_STYLE)
    plot.add(F[chosen : chosen + 1], linewidth=2.5, **CHOSEN_STYLE)
    plot.do()
    return plot.fig


def convergence_figure(records: Sequence[dict]) -> Figure:
    """Normalised hypervolume and feasible count against generation."""
    gen = [r["generation"] for r in records]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    ax1.plot(gen, [r["hypervolume"] for r in records])
    ax1.set(xlabel="generation", ylabel="hypervolume (first-generation scale)")
    ax2.plot(gen, [r["feasible"] for r in records], label="feasible in population")
    ax2.plot(gen, [r["front"] for r in records], label="feasible front size")
    ax2.set(xlabel="generation", ylabel="individuals")
    ax2.legend()
    return fig
