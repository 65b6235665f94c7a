"""The body IMU: the trunk's linear acceleration and pitch rate at the IMU's rate, in its frame.

The accelerometer channel is the linear acceleration (gravity removed with the true attitude, as
an IMU's fusion output gives it), rotated into the trunk frame; the gyro gives the pitch rate.
Each axis gets a constant bias and white Gaussian noise from the climb's seed, so a repeat of a
climb is bit-identical and the noise is the only difference between the IMU and the solver.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


@dataclass(frozen=True)
class ImuModel:
    rate_hz: float
    acc_noise: float = 0.0  # m/s^2, standard deviation per axis
    acc_bias: float = 0.0
    gyro_noise: float = 0.0  # rad/s
    gyro_bias: float = 0.0


def imu_channels(
    t: Array, acc: Array, pitch: Array, pitch_rate: Array, model: ImuModel, seed: int
) -> dict[str, Array]:
    """Sample the trunk's world acceleration (T, 2), pitch and pitch rate at the IMU's rate.

    Returns ``t``, ``acc_x``, ``acc_z`` (trunk frame), ``gyro`` and ``acc`` (the magnitude the
    jitter is read from).
    """
    if t.size == 0:
        empty = np.zeros(0)
        return {k: empty for k in ("t", "acc_x", "acc_z", "gyro", "acc")}
    grid = np.arange(t[0], t[-1] + 1e-12, 1.0 / model.rate_hz)
    ax, az = (np.interp(grid, t, acc[:, i]) for i in (0, 1))
    th = np.interp(grid, t, pitch)
    c, s = np.cos(th), np.sin(th)
    rng = np.random.default_rng(seed)
    bx = c * ax + s * az + model.acc_bias + rng.normal(0.0, model.acc_noise, grid.size)
    bz = -s * ax + c * az + model.acc_bias + rng.normal(0.0, model.acc_noise, grid.size)
    gyro = (
        np.interp(grid, t, pitch_rate)
        + model.gyro_bias
        + rng.normal(0.0, model.gyro_noise, grid.size)
    )
    return {"t": grid, "acc_x": bx, "acc_z": bz, "gyro": gyro, "acc": np.hypot(bx, bz)}
