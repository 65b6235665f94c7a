"""The platform's press loop: an integral force control on the sensor under the plate.

The acquisition presses the pad to the pre-pressure with it, the proof pull, the hold test and the
slip test move the load with it, and the climbing robot's landing press shares its integral.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ftfof.config import Sensor
from ftfof.sim.model import Platform
from ftfof.trajectory.blend import min_jerk

Array = NDArray[np.float64]
PRESS_TIME_CONSTANT = 0.01  # s, integral action of the pre-pressure loop


def press_control(
    p: Platform,
    plate_index: int,
    q: Array,
    qd: Array,
    h: float,
    target: float,
    integral: float,
    feedforward: bool = True,
) -> float:
    """Set the press depth so the sensor reads ``target`` (N, compression positive) by integral
    action on its error, with the depth that presses ``target`` through the foot as feedforward
    unless something else presses it (the slip test's sled); returns the updated integral (the
    caller keeps it between steps)."""
    k = p.series_stiffness
    integral = press_integral(p.spec.platform.sensor, plate_index, q, qd, h, target, integral, k)
    p.press_depth.SetValue((target / k if feedforward else 0.0) + integral)
    return integral


def press_integral(
    sensor: Sensor,
    plate_index: int,
    q: Array,
    qd: Array,
    h: float,
    target: float,
    integral: float,
    stiffness: float,
) -> float:
    """The press loop's integral after a step of ``h``: the depth (m) that brings the force
    ``sensor`` under the plate at ``plate_index`` reads to ``target`` (N, compression positive)
    through a press path of ``stiffness`` (N/m). The platform's press and the climbing robot's
    landing press share it."""
    compression = -sensor_tension(sensor, plate_index, q, qd)
    return integral + (target - compression) / stiffness * min(h / PRESS_TIME_CONSTANT, 1.0)


def press_to_pull(press: float, pull: float, u: float) -> float:
    """The press loop's target at ``u`` of a minimum-jerk move from a press (N) to a pull (N,
    tension positive): the hold test's and the proof pull's ramp."""
    return press - (press + pull) * float(min_jerk(u)[0])


def sensor_tension(sensor: Sensor, plate_index: int, q: Array, qd: Array) -> float:
    """The force ``sensor`` reads under the plate at ``plate_index`` (N, tension positive): its
    spring and damper on the plate's normal coordinate."""
    z = plate_index + 1
    return float(sensor.stiffness * q[z] + sensor.damping * qd[z])
