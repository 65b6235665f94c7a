"""A stance pad's hold on the platform: press the pad, then pull its ankle off the plate and hold.

The climbing robot's fore stance foot is pulled at its ankle when the other fore foot presses its
landing: on a wall the feet's normal forces sum to zero, and the trunk's weight, off the wall,
tips it away, so the fore foot holds a + m g h / L (:func:`ftfof.demand.fore_foot_demand`).
This is that load on the platform: settle and press the pad to the pre-pressure a as a sample
does, then move the normal load from a press to a ``pull`` (N) over ``ramp`` with the press loop
(a force control on the sensor, as a real platform would run it), and keep it for ``hold``
seconds. It reports whether the pad held: how much of it stayed bonded, and how far the ankle
rose from where it was when the pull was reached.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import exudyn as exu
import numpy as np

from ftfof.demand import LET_GO
from ftfof.sim.bonds import BondLaw
from ftfof.sim.model import Platform, build
from ftfof.sim.padstate import PadTracker
from ftfof.sim.press import press_control, press_to_pull, sensor_tension
from ftfof.sim.settings import solver_settings
from ftfof.sim.spec import SampleSpec
from ftfof.trajectory.bezier import Samples
from ftfof.trajectory.blend import min_jerk
from ftfof.trajectory.piecewise import PiecewiseQuintic


@dataclass(frozen=True)
class Hold:
    """What a hold test saw."""

    bonded: float  # the bonded share of the pad at the end
    least_bonded: float  # its least over the hold
    rise: float  # m: the ankle's rise from the pull's arrival to the end
    pull: float  # N: the sensor's mean tension over the hold

    @property
    def held(self) -> bool:
        """The pad held: at least 90 % of it stayed bonded (the proof pull's line, issue 53)."""
        return self.least_bonded >= 1.0 - LET_GO


def at_rest(duration: float) -> PiecewiseQuintic:
    """The commanded foot still at its start for ``duration`` seconds."""
    t = np.array([0.0, duration])
    zero = np.zeros((1, 2, 2))
    return PiecewiseQuintic.from_samples(Samples(t, zero, zero, zero))


class _HoldStep:
    """Pre-step: the pad's bonds, the press loop on the load schedule, and the record."""

    def __init__(self, p: Platform, solver: exu.MainSolverImplicitSecondOrder, pull: float):
        self.p, self.solver, self.pull = p, solver, pull
        self.data = p.mbs.systemData
        s = p.spec
        self.pad = PadTracker(
            p.mbs, p.pad_parts(), p.law, p.initial_pressure, s.mechanics.film.stop_radius
        )
        proto = s.platform.protocol
        self.settle, self.press = proto.settle, proto.press
        self.pressed = proto.settle + proto.press
        self.loaded = self.pressed + proto.press_hold
        self.integral = 0.0
        self.foot = int(p.mbs.GetNodeODE2Index(p.foot_node))
        self.start_z = np.nan
        self.least = 1.0
        self.tension: list[float] = []

    def target(self, t: float) -> float:
        """a by a minimum-jerk press, then on to the pull (a negative press) over the ramp."""
        a = self.p.spec.pre_pressure
        if t < self.pressed:
            return a * float(min_jerk((t - self.settle) / self.press)[0])
        u = min((t - self.pressed) / (self.loaded - self.pressed), 1.0)
        return press_to_pull(a, self.pull, u)

    def __call__(self, mbs, t: float) -> bool:
        q = self.data.GetODE2Coordinates(copy=False)
        qd = self.data.GetODE2Coordinates_t(copy=False)
        h = self.solver.it.currentStepSize
        step = self.pad.update(q, qd, h, t)
        self.integral = press_control(
            self.p, self.pad.plate_index, q, qd, h, self.target(t), self.integral
        )
        if t >= self.loaded:
            if np.isnan(self.start_z):
                self.start_z = float(q[self.foot + 1])
            self.least = min(self.least, step.bonded / len(self.p.film_nodes))
            sensor = self.p.spec.platform.sensor
            self.tension.append(sensor_tension(sensor, self.pad.plate_index, q, qd))
        return bool(np.isfinite(q).all())


def hold_test(spec: SampleSpec, pull: float, ramp: float, hold: float) -> Hold:
    """Press ``spec``'s pad, pull its ankle with ``pull`` (N) reached over ``ramp`` (s), hold it
    ``hold`` (s); ``spec``'s trajectory is replaced by the foot at rest and its landing hold
    dropped."""
    exu.config.printToConsole = False
    protocol = spec.platform.protocol.model_copy(update={"press_hold": ramp, "landing_hold": 0.0})
    run = replace(
        spec,
        trajectory=at_rest(hold),
        proof_pull=None,  # this test is its own pull
        platform=spec.platform.model_copy(update={"protocol": protocol}),
    )
    law = BondLaw.from_surface(run.surface, run.solver.contact_smoothing)
    platform = build(run, law)
    solver = exu.MainSolverImplicitSecondOrder()
    step = _HoldStep(platform, solver, pull)
    platform.mbs.SetPreStepUserFunction(step)
    sensor = run.platform.sensor
    solver.SolveSystem(
        platform.mbs, solver_settings(run.solver, run.end_time, run.solver.step, sensor.rate_hz)
    )
    t_end = platform.mbs.systemData.GetTime()
    if t_end < run.end_time - 1e-9:
        raise RuntimeError(f"the hold test at {pull:g} N stopped at t = {t_end:.4f} s")
    q = platform.mbs.systemData.GetODE2Coordinates()
    bonded = float((~step.pad.state.broken).mean())
    rise = float(q[step.foot + 1]) - step.start_z
    return Hold(bonded, step.least, rise, float(np.mean(step.tension)))


def holding_capacity(
    spec: SampleSpec, ramp: float, hold: float, upper: float, resolution: float = 0.1
) -> float:
    """The largest pull (N) ``spec``'s pad holds for ``hold`` seconds, by bisection on
    :func:`hold_test` to ``resolution`` below ``upper`` (which it must not hold)."""
    low, high = 0.0, upper
    if hold_test(spec, high, ramp, hold).held:
        raise ValueError(f"the pad holds {upper:g} N: raise the bisection's upper bound")
    while high - low > resolution:
        mid = 0.5 * (low + high)
        low, high = (mid, high) if hold_test(spec, mid, ramp, hold).held else (low, mid)
    return low
