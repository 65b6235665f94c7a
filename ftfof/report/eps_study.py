"""The ε study's figure: the landing's pre-pressure over time at each ε (the seed's Fig. 15-16),
and the landing impact and body jitter against ε."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from ftfof.study.eps import EpsStudy


def eps_figure(study: EpsStudy) -> Figure:
    """Each ε's landing over time, and the landing impact and body jitter against ε."""
    points, landings, press_target = study.points, study.landings, study.press
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), constrained_layout=True)
    ax = axes[0, 0]
    for eps, (t, Fp) in landings.items():
        ax.plot(t, Fp, label=f"ε = {eps:g}")
    ax.axhline(press_target, color="k", ls=":", lw=1, label=f"press a = {press_target:g} N")
    # from shortly before the first foot presses a tenth of its peak (the filter's tail after
    # detachment reads a few mN)
    pressed = [t[Fp >= 0.1 * Fp.max()][0] for t, Fp in landings.values() if Fp.max() > 0]
    if pressed:
        ax.set_xlim(left=min(pressed) - 0.05)
    ax.set(xlabel="t from trajectory start [s]", ylabel="Fp [N]", title="landing pre-pressure")
    ax.legend(fontsize=8)
    eps = [p.eps for p in points]
    ax = axes[0, 1]
    ax.plot(eps, [p.landing_pre_pressure for p in points], marker="o", label="peak")
    ax.plot(eps, [p.held_pre_pressure for p in points], marker="s", label="held at the end")
    ax.axhline(press_target, color="k", ls=":", lw=1, label="press a")
    ax.legend()
    ax.set(xlabel="ε", ylabel="peak Fp [N]", title="landing impact: pre-pressure")
    ax = axes[1, 0]
    ax.plot(eps, [p.landing_rate for p in points], marker="o")
    ax.set(xlabel="ε", ylabel="peak dFp/dt [N/s]", title="landing impact: peak rise rate")
    ax = axes[1, 1]
    ax.plot(eps, [p.peak_body_acc for p in points], marker="o", label="whole run")
    ax.plot(eps, [p.detachment_jitter for p in points], marker="s", label="detachment (fsj)")
    ax.set(xlabel="ε", ylabel="peak |a| [m/s²]", title="body jitter")
    ax.legend()
    fig.suptitle("ε-Bezier baseline on the platform, swept over ε")
    return fig
