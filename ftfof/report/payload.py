"""The payload study's figure: per trajectory, the heaviest added trunk mass it climbed with and
the lightest it fell with (the margin lies between)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.figure import Figure


def payload_figure(margins: Mapping[str, Mapping[str, Any]], title: str) -> Figure:
    """A bar per trajectory to its margin, a tick where it fell; one that climbed at the ceiling
    is marked so, one that fell unloaded has no bar."""
    names = list(margins)
    fig, ax = plt.subplots(figsize=(8, 0.5 * len(names) + 1.6), constrained_layout=True)
    grams = [1e3 * margins[n]["payload"] for n in names]
    ax.barh(names, grams, color="tab:blue", label="climbed every step")
    for i, n in enumerate(names):
        m = margins[n]
        if m["fell_with"] is not None:
            ax.plot(1e3 * m["fell_with"], i, "x", color="tab:red", ms=9)
        if not m["climbs_unloaded"]:
            ax.text(0, i, "  falls unloaded", va="center", color="tab:red")
        elif m["fell_with"] is None:
            ax.text(grams[i], i, "  climbed at the ceiling", va="center")
    ax.plot([], [], "x", color="tab:red", label="fell")
    ax.invert_yaxis()
    ceiling = max(1e3 * m["ceiling"] for m in margins.values())
    ax.set_xlim(0, 1.45 * ceiling)  # room for the notes beside the bars
    ax.set(xlabel="mass added to the trunk [g]", title=title)
    ax.legend(loc="lower right", fontsize=8, framealpha=1)
    return fig
