"""A slip test on the platform: press the pad, set a normal load, drag it along the plate.

Per normal load (N, compression positive, a pull negative) one fresh pad: settle, press it to
the preload a (the acquisition's press loop), move the load to its value over ``press_hold``,
then drag the foot along +x at a constant speed while the press loop holds the load. The bonds
shear off at the law's allowance |tau| <= s tau_max + mu p (:mod:`ftfof.sim.bonds`), so the peak
tangential force of each load lies on F_t = mu (F_n + F_adh), which
:mod:`ftfof.identify` estimates. The sensor's Fx and Fz are recorded at its rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

from ftfof.identify.log import SlipLog
from ftfof.sim.bonds import BondLaw
from ftfof.sim.model import Platform, build
from ftfof.sim.padstate import PadTracker
from ftfof.sim.prestep import press_control
from ftfof.sim.settings import solver_settings
from ftfof.sim.spec import SampleSpec
from ftfof.trajectory.bezier import Samples
from ftfof.trajectory.piecewise import PiecewiseQuintic

Array = NDArray[np.float64]
RAMP = 0.02  # s to reach the drag speed


@dataclass(frozen=True)
class SlipProtocol:
    """The loads and the drag of one slip test."""

    loads: tuple[float, ...]  # normal loads, N, compression positive (a pull negative)
    speed: float  # drag speed of the commanded foot, m/s
    drag: float  # commanded drag distance, m
    ankle_stiffness: float  # N m/rad: the test fixture locks the passive ankle, which would
    # otherwise turn the drag into a peel about the heel


def drag(speed: float, distance: float) -> PiecewiseQuintic:
    """The foot at rest, up to ``speed`` along +x over RAMP, then steady over ``distance``."""
    duration = RAMP + (distance - speed * RAMP / 2) / speed
    t = np.array([0.0, RAMP, duration])
    x = np.array([0.0, speed * RAMP / 2, distance])
    v = np.array([0.0, speed, speed])
    pos = np.stack([x, np.zeros(3)], axis=-1)[None]
    vel = np.stack([v, np.zeros(3)], axis=-1)[None]
    return PiecewiseQuintic.from_samples(Samples(t, pos, vel, np.zeros_like(pos)))


class _SlipStep:
    """Pre-step of one slip run: the pad's bonds and the press loop on the load schedule."""

    def __init__(self, p: Platform, solver: exu.MainSolverImplicitSecondOrder, load: float):
        self.p, self.solver, self.load = p, solver, load
        self.data = p.mbs.systemData
        s = p.spec
        self.pad = PadTracker(
            p.mbs, p.pad_parts(), p.law, p.initial_pressure, s.mechanics.film.stop_radius
        )
        proto = s.platform.protocol
        self.settle, self.press, self.hold = proto.settle, proto.press, proto.press_hold
        self.integral = 0.0

    def target(self, t: float) -> float:
        """Preload a by a minimum-jerk press, then on to the load over the hold."""
        a = self.p.spec.pre_pressure
        if t < self.settle + self.press:
            u = min(max((t - self.settle) / self.press, 0.0), 1.0)
            return a * _min_jerk(u)
        u = min((t - self.settle - self.press) / self.hold, 1.0)
        return a + (self.load - a) * _min_jerk(u)

    def __call__(self, mbs, t: float) -> bool:
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        h = self.solver.it.currentStepSize
        self.pad.update(q, qd, h, t)
        self.integral = press_control(
            self.p, self.pad.plate_index, q, qd, h, self.target(t), self.integral
        )
        return bool(np.isfinite(q).all())


def _min_jerk(u: float) -> float:
    return u * u * u * (10 - 15 * u + 6 * u * u)


def slip_run(spec: SampleSpec, load: float) -> tuple[Array, Array, Array]:
    """One load's run: (t from the drag's start, Fx, Fz) at the sensor rate, filtered as the
    sensor is, with its noise (seeded by the spec)."""
    from scipy import signal

    exu.config.printToConsole = False
    law = BondLaw.from_surface(spec.surface, spec.solver.contact_smoothing)
    platform = build(spec, law)
    solver = exu.MainSolverImplicitSecondOrder()
    platform.mbs.SetPreStepUserFunction(_SlipStep(platform, solver, load))
    sensor = spec.platform.sensor
    solver.SolveSystem(
        platform.mbs,
        solver_settings(spec.solver, spec.end_time, spec.solver.step, sensor.rate_hz),
    )
    t_end = platform.mbs.systemData.GetTime()
    if t_end < spec.end_time - 1e-9:
        raise RuntimeError(f"slip run at {load:g} N stopped at t = {t_end:.4f} s")
    t = np.arange(spec.trajectory_start, t_end + 1e-12, 1.0 / sensor.rate_hz)
    b, a = signal.butter(2, sensor.cutoff_hz / (sensor.rate_hz / 2))
    rng = np.random.default_rng(spec.seed)

    def measured(name: str) -> Array:
        raw = np.asarray(platform.mbs.GetSensorStoredData(platform.sensors[name]))
        full = np.arange(0.0, t_end + 1e-12, 1.0 / sensor.rate_hz)
        clean = signal.lfilter(b, a, np.interp(full, raw[:, 0], raw[:, 1]))[-t.size :]
        return clean + rng.normal(0.0, sensor.noise, t.size) if sensor.noise > 0 else clean

    return t - spec.trajectory_start, measured("Fx"), measured("Fz")


def slip_test(spec: SampleSpec, protocol: SlipProtocol) -> SlipLog:
    """Every load of ``protocol`` on a fresh pad of ``spec`` (its trajectory is replaced by the
    drag, its landing hold dropped); the runs one after the other on one time axis."""
    traj = drag(protocol.speed, protocol.drag)
    platform = spec.platform.model_copy(
        update={"protocol": spec.platform.protocol.model_copy(update={"landing_hold": 0.0})}
    )
    m = spec.mechanics
    foot = m.foot.model_copy(update={"ankle_stiffness": protocol.ankle_stiffness})
    mechanics = m.model_copy(update={"foot": foot})
    parts: list[tuple[Array, Array, Array]] = []
    for i, load in enumerate(protocol.loads):
        run = replace(
            spec, trajectory=traj, platform=platform, mechanics=mechanics, seed=spec.seed + i
        )
        parts.append(slip_run(run, load))
    step = 1.0 / spec.platform.sensor.rate_hz
    offsets = np.cumsum([0.0] + [p[0][-1] - p[0][0] + step for p in parts[:-1]])
    t = np.concatenate([p[0] - p[0][0] + o for p, o in zip(parts, offsets, strict=True)])
    loads = np.concatenate(
        [np.full(p[0].size, load) for p, load in zip(parts, protocol.loads, strict=True)]
    )
    return SlipLog(
        t=t,
        Fx=np.concatenate([p[1] for p in parts]),
        Fz=np.concatenate([p[2] for p in parts]),
        load=loads,
    )


def adhesion_truth(law: BondLaw, preload: float, area: float) -> float:
    """F_adh per pad the bond law implies: at slip the pad holds sum_i (s tau_max + mu p_i) A_i
    = s tau_max A + mu F_n, i.e. mu (F_n + F_adh) with F_adh = s tau_max A / mu, s the preload
    factor of the preload spread over the pad (the reset's bond) with no rate or damage."""
    s = float(law.preload_factor(preload / area))
    return s * law.shear_strength * area / law.friction if law.friction > 0 else math.inf


def strength_for(law: BondLaw, preload: float, area: float, mu: float, adhesion: float) -> float:
    """The shear strength tau_max whose allowance gives ``adhesion`` per pad at ``preload``
    (:func:`adhesion_truth` solved for tau_max)."""
    return mu * adhesion / (float(law.preload_factor(preload / area)) * area)
