"""Figures as matplotlib objects (the stages save them); Agg backend, no display needed."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from ftfof.data.targets import TARGETS


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


def dataset_figure(table, n: int, seed: int) -> Figure:
    """A few training sequences: foot path and the force targets on the time base."""
    rows = [i for i, s in enumerate(table.column("split").to_pylist()) if s == "train"]
    pick = np.random.default_rng(seed).choice(rows, size=min(n, len(rows)), replace=False)
    fig, axes = plt.subplots(
        len(pick), 2, figsize=(10, 2.4 * len(pick)), constrained_layout=True, squeeze=False
    )
    for ax_row, i in zip(axes, sorted(pick), strict=True):
        names = ("t", "x", "z", "pull", "Fd", "Fp")
        row = {k: np.asarray(table.column(k)[int(i)].as_py()) for k in names}
        ax_row[0].plot(row["x"] * 1e3, row["z"] * 1e3)
        ax_row[0].set(xlabel="x [mm]", ylabel="z [mm]", title=table.column("key")[int(i)].as_py())
        ax_row[1].plot(row["t"], row["pull"], label="pull |F|")
        ax_row[1].plot(row["t"], row["Fd"], "--", label="Fd (normal)")
        ax_row[1].plot(row["t"], row["Fp"], label="Fp (landing)")
        ax_row[1].set(xlabel="t [s]", ylabel="N")
        ax_row[1].legend()
    return fig


TITLES = {
    "pull": "pull |F| [N]",
    "Fd": "normal tension Fd [N]",
    "Fp": "landing pre-pressure Fp [N]",
    "jitter": "fs7 running exceedance sum",
    "body_acc": "body acceleration [m/s²]",
    "curvature": "film curvature [1/m]",
    "clearance": "pad clearance [m]",
    "retouch": "bonds formed again in the swing [bonds]",
    "holds": "the landed pad held F_proof [1: yes]",
}


def loss_figure(results: list[dict]) -> Figure:
    """FTFOF Fig. 8: per-epoch losses of every model (one per loss, each on its own scale)."""
    fig, axes = plt.subplots(1, len(results), figsize=(5 * len(results), 3.2),
                             constrained_layout=True, squeeze=False)  # fmt: skip
    for ax, r in zip(axes[0], results, strict=True):
        h = r["history"]
        ax.plot(h["train"], label="train")
        ax.plot(h["validation"], label="validation")
        ax.axvline(h["best_epoch"], color="grey", ls=":", lw=1)
        ax.set(title=f"all targets, {r['kind']} loss", xlabel="epoch", ylabel="loss")
        ax.set_yscale("log")
        ax.legend()
    return fig


def prediction_figure(results: list[dict], data, seed: int, n: int = 3) -> Figure:
    """FTFOF Fig. 9: predicted vs measured targets on validation samples, per loss."""
    t = np.asarray(data.table.column("t")[0].as_py())
    first = results[0]["val_truth"]
    pick = np.random.default_rng(seed).choice(len(first), size=min(n, len(first)), replace=False)
    targets = [name for name in TARGETS if name in results[0]["metrics"]]
    fig, axes = plt.subplots(len(targets), len(pick), figsize=(4.2 * len(pick), 2.8 * len(targets)),
                             constrained_layout=True, squeeze=False)  # fmt: skip
    for row, target in enumerate(targets):
        k = TARGETS.index(target)
        for col, i in enumerate(pick):
            ax = axes[row, col]
            ax.plot(t, first[i, :, k], color="black", lw=2, label="simulated")
            for r in results:
                ax.plot(t, r["val_pred"][i, :, k], label=f"GRU, {r['kind']}")
            ax.set(title=f"validation sample {i}", xlabel="t [s]", ylabel=TITLES[target])
            ax.legend(fontsize=7)
    return fig
