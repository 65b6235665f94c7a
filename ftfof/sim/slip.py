"""A slip test on the platform: press the pad, set a normal load, drag it along the plate.

Per normal load (N, compression positive) one fresh pad: settle, press it to the preload a,
move the load to its value over ``press_hold``, then drag the foot along +x at a constant speed
while the load holds. The load presses as a tribometer's sled does, spread over the pad by
area (:func:`_sled`), and the press loop keeps the foot's own press at nil; pressed through the
foot's grip, the pad would be pressed and preloaded at its heel alone and lift elsewhere. The bonds
shear off at their own strength and the friction sliders beside them hold mu times the load
(:mod:`ftfof.sim.bonds`), so the peak tangential force of each load lies on
F_t = mu F_n + F_adh(v) (:func:`adhesion_truth`), which :mod:`ftfof.identify` estimates. The
sensor's Fx and Fz are recorded at its rate.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import exudyn as exu
import numpy as np
from exudyn.advancedUtilities import CreateSymbolicUserFunction
from exudyn.itemInterface import LoadForceVector, MarkerNodePosition
from numpy.typing import NDArray

from ftfof.identify.log import SlipLog
from ftfof.sim.bonds import BondLaw
from ftfof.sim.model import Platform, build
from ftfof.sim.padstate import PadTracker
from ftfof.sim.press import press_control
from ftfof.sim.settings import solver_settings
from ftfof.sim.spec import SampleSpec
from ftfof.trajectory.bezier import Samples
from ftfof.trajectory.blend import min_jerk
from ftfof.trajectory.piecewise import PiecewiseQuintic

Array = NDArray[np.float64]
RAMP = 0.02  # s to reach the drag speed
esym = exu.symbolic


@dataclass(frozen=True)
class SlipProtocol:
    """The loads and the drag of one slip test."""

    loads: tuple[float, ...]  # normal loads, N, compression positive (a pull negative)
    speed: float  # drag speed of the commanded foot, m/s
    drag: float  # commanded drag distance, m
    ankle_stiffness: float  # N m/rad: the test fixture locks the passive ankle, which would
    # otherwise turn the drag into a peel about the heel
    drive_stiffness: float  # N/m along the drag: the leg and its mount, stiff as a drag stage's
    drive_height: float  # m above the pad where the drive holds the foot (its ankle height): a
    # lap-shear fixture pulls in the pad's plane, so the drag puts no moment on the pad
    coupon_modulus: float  # Pa: a plate foot's pad is tested on a stiff coupon, not its foam,
    # which would shear millimetres and load the bonds far slower than the drag (the test
    # identifies the surface, not the foot)


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

    def __init__(
        self, p: Platform, solver: exu.MainSolverImplicitSecondOrder, load: float, sled: Any
    ):
        self.p, self.solver, self.load, self.sled = p, solver, load, sled
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
            return a * float(min_jerk(u)[0])
        u = min((t - self.settle - self.press) / self.hold, 1.0)
        return a + (self.load - a) * float(min_jerk(u)[0])

    def __call__(self, mbs, t: float) -> bool:
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        h = self.solver.it.currentStepSize
        self.pad.update(q, qd, h, t)
        target = self.target(t)
        self.sled.SetValue(target)
        self.integral = press_control(
            self.p, self.pad.plate_index, q, qd, h, target, self.integral, feedforward=False
        )
        return bool(np.isfinite(q).all())


def _sled(p: Platform) -> Any:
    """A normal load on every film node in proportion to its pad area, their total a named
    symbolic variable (N, compression positive) the pre-step sets: one value per step, however
    many nodes. Re-assembles the system."""
    total = esym.Real("sled", 0.0)

    def share(mbs, t, loadVector):
        return [0, -total * loadVector[1], 0]

    law = CreateSymbolicUserFunction(
        p.mbs, share, "loadVectorUserFunction", itemTypeName="LoadForceVector"
    )
    for node, area in zip(p.film_nodes, p.area / p.area.sum(), strict=True):
        marker = p.mbs.AddMarker(MarkerNodePosition(nodeNumber=node))
        load = p.mbs.AddLoad(LoadForceVector(markerNumber=marker, loadVector=[0.0, area, 0.0]))
        p.mbs.SetLoadParameter(load, "loadVectorUserFunction", law)
    p.keep.extend([law, total])
    p.mbs.Assemble()
    return total


def slip_run(spec: SampleSpec, load: float) -> tuple[Array, Array, Array]:
    """One load's run: (t from the drag's start, Fx, Fz) at the sensor rate, filtered as the
    sensor is, with its noise (seeded by the spec)."""
    from scipy import signal

    exu.config.printToConsole = False
    law = BondLaw.from_surface(spec.surface, spec.solver.contact_smoothing)
    platform = build(spec, law)
    solver = exu.MainSolverImplicitSecondOrder()
    platform.mbs.SetPreStepUserFunction(_SlipStep(platform, solver, load, _sled(platform)))
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


def slip_test(
    spec: SampleSpec, protocol: SlipProtocol, trajectory: PiecewiseQuintic | None = None
) -> SlipLog:
    """Every load of ``protocol`` on a fresh pad of ``spec`` (its trajectory is replaced by the
    drag, or by ``trajectory``: a hold, say; its landing hold dropped); the runs one after the
    other on one time axis."""
    traj = drag(protocol.speed, protocol.drag) if trajectory is None else trajectory
    platform = spec.platform.model_copy(
        update={"protocol": spec.platform.protocol.model_copy(update={"landing_hold": 0.0})}
    )
    m = spec.mechanics
    foot = m.foot.model_copy(
        update={"ankle_stiffness": protocol.ankle_stiffness, "ankle_height": protocol.drive_height}
    )
    if foot.backing is not None:
        coupon = foot.backing.model_copy(update={"modulus": protocol.coupon_modulus})
        foot = foot.model_copy(update={"backing": coupon})
    stiff = protocol.drive_stiffness
    leg = m.leg_stiffness.model_copy(update={"x": stiff})
    body = m.body.model_copy(
        update={"mount_stiffness": m.body.mount_stiffness.model_copy(update={"x": stiff})}
    )
    mechanics = m.model_copy(update={"foot": foot, "leg_stiffness": leg, "body": body})
    parts: list[tuple[Array, Array, Array]] = []
    for i, load in enumerate(protocol.loads):
        run = replace(
            spec,
            trajectory=traj,
            platform=platform,
            mechanics=mechanics,
            seed=spec.seed + i,
            ankle_rest=0.0,  # the fixture holds the plate flat
            proof_pull=None,
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


def adhesion_truth(law: BondLaw, preload: float, area: float, speed: float = 0.0) -> float:
    """F_adh(v) = R(v) F_adh,0 per pad, N, of a slip test dragged at ``speed``: at slip the pad's
    bonds hold their strength whatever the load and friction adds mu F_n, F_t = mu F_n + F_adh.
    F_adh,0 = phi tau_max A, phi the preload factor of the preload spread over the pad (the
    reset's bond) with no damage; R(v) the rate factor of a bond sheared at the drag speed
    (:meth:`BondLaw.drag_rate_factor`; 1 at ``speed`` 0, the quasi-static F_adh,0)."""
    phi = float(law.preload_factor(preload / area))
    return law.drag_rate_factor(speed) * phi * law.shear_strength * area


def strength_for(law: BondLaw, preload: float, area: float, adhesion: float) -> float:
    """The shear strength tau_max whose quasi-static F_adh,0 per pad at ``preload`` is
    ``adhesion`` (:func:`adhesion_truth` at speed 0, solved for tau_max)."""
    return adhesion / (float(law.preload_factor(preload / area)) * area)
