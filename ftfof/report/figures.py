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


def dataset_figure(table, n: int, seed: int) -> Figure:
    """A few training sequences: foot path and the two force targets on the time base."""
    rows = [i for i, s in enumerate(table.column("split").to_pylist()) if s == "train"]
    pick = np.random.default_rng(seed).choice(rows, size=min(n, len(rows)), replace=False)
    fig, axes = plt.subplots(
        len(pick), 2, figsize=(10, 2.4 * len(pick)), constrained_layout=True, squeeze=False
    )
    for ax_row, i in zip(axes, sorted(pick), strict=True):
        row = {k: np.asarray(table.column(k)[int(i)].as_py()) for k in ("t", "x", "z", "Fd", "Fp")}
        ax_row[0].plot(row["x"] * 1e3, row["z"] * 1e3)
        ax_row[0].set(xlabel="x [mm]", ylabel="z [mm]", title=table.column("key")[int(i)].as_py())
        ax_row[1].plot(row["t"], row["Fd"], label="Fd")
        ax_row[1].plot(row["t"], row["Fp"], label="Fp")
        ax_row[1].set(xlabel="t [s]", ylabel="N")
        ax_row[1].legend()
    return fig


def loss_figure(results: list[dict]) -> Figure:
    """FTFOF Fig. 8: per-epoch losses of every model (each loss on its own scale)."""
    targets = sorted({r["target"] for r in results}, key=["Fp", "Fd"].index)
    kinds = sorted({r["kind"] for r in results})
    fig, axes = plt.subplots(len(kinds), len(targets), figsize=(5 * len(targets), 3.2 * len(kinds)),
                             constrained_layout=True, squeeze=False)  # fmt: skip
    for r in results:
        ax = axes[kinds.index(r["kind"]), targets.index(r["target"])]
        h = r["history"]
        ax.plot(h["train"], label="train")
        ax.plot(h["validation"], label="validation")
        ax.axvline(h["best_epoch"], color="grey", ls=":", lw=1)
        name = {"Fp": "pre-pressure", "Fd": "detachment"}[r["target"]]
        ax.set(title=f"{name} ({r['target']}), {r['kind']} loss", xlabel="epoch", ylabel="loss")
        ax.set_yscale("log")
        ax.legend()
    return fig


def prediction_figure(results: list[dict], data, seed: int, n: int = 3) -> Figure:
    """FTFOF Fig. 9: predicted vs measured force on validation samples, per loss."""
    t = np.asarray(data.table.column("t")[0].as_py())
    first = results[0]["val_truth"]
    pick = np.random.default_rng(seed).choice(len(first), size=min(n, len(first)), replace=False)
    targets = sorted({r["target"] for r in results}, key=["Fp", "Fd"].index)
    fig, axes = plt.subplots(len(targets), len(pick), figsize=(4.2 * len(pick), 3.2 * len(targets)),
                             constrained_layout=True, squeeze=False)  # fmt: skip
    for row, target in enumerate(targets):
        mine = [r for r in results if r["target"] == target]
        for col, i in enumerate(pick):
            ax = axes[row, col]
            ax.plot(t, mine[0]["val_truth"][i], color="black", lw=2, label="measured (simulated)")
            for r in mine:
                ax.plot(t, r["val_pred"][i], label=f"GRU, {r['kind']}")
            ax.set(title=f"{target}, validation sample {i}", xlabel="t [s]", ylabel="N")
            ax.legend(fontsize=8)
    return fig
