"""The climb's traces (as FTFOF Fig. 14 shows its IMU): jitter, body path, pad forces, bonds;
and the climb from the side."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import NDArray

from ftfof.climb.metrics import stance_travel
from ftfof.climb.outcome import Climbed
from ftfof.climb.simulate import chain_of
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


def climb_filmstrip(
    channels: dict[str, Array],
    frames: list[float],
    hips: Array,
    hip_height: float,
    links: tuple[float, float],
    ankle_height: float,
    pad_length: float,
    title: str,
) -> Figure:
    """The robot from the side at ``frames`` (s): the wall vertical on the left, x up it, the
    trunk, each leg's thigh, shank and foot, and each pad on the wall (red while it lets go)."""
    c = channels
    fig, axes = plt.subplots(1, len(frames), figsize=(1.9 * len(frames), 5.2), sharey=True,
                             constrained_layout=True)  # fmt: skip
    axes = np.atleast_1d(axes)
    l1, l2 = links
    for ax, when in zip(axes, frames, strict=True):
        i = int(np.clip(np.searchsorted(c["t"], when), 0, len(c["t"]) - 1))
        bx, bz, pitch = c["body"][i]
        base = np.array([bx, hip_height + bz])
        along = np.array([np.cos(pitch), np.sin(pitch)])
        ax.axvline(0.0, color="0.4", lw=3)
        ends = np.array([base + h * along for h in (hips.min(), hips.max())])
        ax.plot(1e3 * ends[:, 1], 1e3 * ends[:, 0], color="k", lw=5, solid_capstyle="round")
        for leg, name in enumerate(LEG_NAMES):
            hip = base + hips[leg] * along
            q = c["joints"][i, 3 * leg : 3 * leg + 3]
            a1, a2 = pitch + q[0], pitch + q[0] + q[1]
            knee = hip + l1 * np.array([np.cos(a1), np.sin(a1)])
            ankle = knee + l2 * np.array([np.cos(a2), np.sin(a2)])
            foot = np.array([c["foot"][i, 2 * leg], c["foot"][i, 2 * leg + 1] - ankle_height])
            colour = f"C{leg}"
            chain = np.array([hip, knee, ankle, foot])
            ax.plot(1e3 * chain[:, 1], 1e3 * chain[:, 0], "-o", color=colour, ms=2, lw=1.2,
                    label=name)  # fmt: skip
            held = c["bonds"][i, leg] > 0
            pad_z = max(foot[1], 0.0)
            ax.plot([1e3 * pad_z] * 2, 1e3 * np.array([foot[0], foot[0] + pad_length]),
                    color=colour if held else "red", lw=3)  # fmt: skip
        ax.set_title(f"t = {c['t'][i]:.2f} s", fontsize=9)
        ax.set_xlim(-5, 1e3 * (hip_height + l1 + 0.02))
        ax.set_xlabel("z [mm]")
    axes[0].set_ylabel("x up the wall [mm]")
    axes[0].legend(loc="lower right", fontsize=7)
    fig.suptitle(title)
    return fig


def climb_traces(out: Climbed, title: str) -> Figure:
    """:func:`climb_figure` of a measured climb, each of its steps' swings shaded."""
    gait = out.run.gait
    swings = [(gait.lift_off(k), gait.lift_off(k) + gait.swing) for k in range(len(out.steps))]
    return climb_figure(out.run.channels, out.imu, swings, title)


def side_view(out: Climbed, title: str) -> Figure:
    """The climb from the side: each step's swing a third of the way in, and the last moment."""
    run, spec = out.run, out.run.spec
    chain = chain_of(spec.robot)
    gait = run.gait
    end = float(run.channels["t"][-1]) if run.channels["t"].size else 0.0
    frames = [gait.lift_off(k) + gait.swing / 3 for k in range(len(out.steps))]
    frames = [f for f in frames if f < end] + [end]
    return climb_filmstrip(
        run.channels,
        frames,
        gait.hips,
        float(chain.hip[1]),
        chain.links,
        spec.robot.platform.foot.ankle_height,
        spec.robot.foot.pad_length,
        f"{title}: from the side",
    )


def slip_comparison_figure(runs: dict[str, Climbed], leg: int, title: str) -> Figure:
    """One foot's slip under each controller (``runs``: controller -> its climb): its slip
    velocity, and how far its pad got from where each stance began (the slip distance sums
    each stance's largest excursion)."""
    fig, axes = plt.subplots(2, 1, figsize=(11, 6.5), sharex=True, constrained_layout=True)
    for controller, out in runs.items():
        c = out.run.channels
        t, v = c["t"], c["slip_velocity"][:, leg]
        distance = 1e3 * out.slip.distance[leg]
        axes[0].plot(t, 1e3 * v, lw=0.6, label=controller)
        axes[1].plot(t, 1e3 * stance_travel(t, v), lw=0.9, label=f"{controller}: {distance:.2f} mm")
    axes[0].set(ylabel=f"{LEG_NAMES[leg]} slip velocity [mm/s]", title=title)
    axes[1].set(xlabel="t [s]", ylabel="from the stance's start [mm]")
    axes[0].legend(loc="upper left", ncols=4, fontsize=8)
    axes[1].legend(loc="lower left", title=f"{LEG_NAMES[leg]}'s slip distance", fontsize=8)
    return fig
