"""Simulate one climb: build the robot, run the crawl, return its channels (docs/climb.md).

A fall ends the run cleanly with what was recorded so far (``fell`` and why); a solver error or
a non-finite state makes the climb ``failed`` with the message, never an exception.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field

import exudyn as exu
import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.climb.control.com_replan import PlannerReplanner
from ftfof.climb.control.controllers import compose
from ftfof.climb.control.feedforward import FeedForward
from ftfof.climb.control.replan import Replanner
from ftfof.climb.control.slip import SlipDetector
from ftfof.climb.control.state import Pads, SlipEstimate
from ftfof.climb.gait import LEGS, Gait
from ftfof.climb.legs import SagittalChain, sagittal_chain
from ftfof.climb.loop import ClimbLoop, channel_slices
from ftfof.climb.model import Climber, ClimbSpec, build
from ftfof.demand import robot_mass
from ftfof.sim.bonds import BondLaw
from ftfof.sim.settings import solver_settings
from ftfof.sim.slip import adhesion_truth

Array = NDArray[np.float64]


@dataclass
class ClimbRun:
    """The raw outcome of one climb: channels at the record rate and how the run ended."""

    spec: ClimbSpec
    gait: Gait
    channels: dict[str, Array]
    fell: bool
    fall_reason: str
    error: str  # "" unless the solver failed or the run was stopped
    wall_time: float
    steps: int  # solver steps
    imu_reference: Array = field(repr=False)  # (T, 4) t, ax, az, angular acc. from the solver
    control: dict[str, int] = field(default_factory=dict)  # what the controller did, if any
    estimates: list[SlipEstimate] = field(default_factory=list)  # its estimator's, per slip

    @property
    def ok(self) -> bool:
        return not self.error


def chain_of(robot: config.Robot) -> SagittalChain:
    """The robot's leg as the climbing model's planar chain."""
    if robot.climber is None:
        raise ValueError("the robot has no climber block: it cannot climb")
    return sagittal_chain(robot.leg, robot.climber.torque_limits, robot.platform.foot.ankle_height)


def gait_of(spec: ClimbSpec) -> Gait:
    """The crawl of ``spec``'s trajectory on its robot, with the platform's press protocol."""
    climber = spec.robot.climber
    chain = chain_of(spec.robot)
    assert climber is not None
    half = climber.hip_spacing / 2
    proto = spec.platform.protocol
    return Gait(
        trajectory=spec.trajectory,
        order=climber.gait,
        steps=spec.climb.steps,
        start=proto.settle + proto.press + proto.press_hold,
        hold=proto.landing_hold,
        shift=spec.climb.shift_time,
        hips=np.array([half, half, -half, -half]),
        foot_start=-chain.hip,
    )


def controller_of(model: Climber, replanner: Replanner) -> FeedForward | None:
    """The stance feet's force control ``climb.controller`` asks for (None: off), composed by
    its name (:func:`~ftfof.climb.control.controllers.compose`; ``replanner`` for the parts that
    re-plan). It believes every pad is on the selected surface, pressed to the pre-pressure:
    F_adh as the bond law gives it (:func:`ftfof.sim.slip.adhesion_truth`, quasi-static), taken
    as its cone's shift F_adh / mu, and its pull-off (:func:`pull_off_of`)."""
    spec = model.spec
    name = spec.climb.controller
    if name is None:
        return None
    climber = spec.robot.climber
    assert climber is not None
    area = float(model.pads[0].area.sum())
    adhesion = adhesion_truth(model.law, spec.robot.pre_pressure, area) / model.law.friction
    pull_off = pull_off_of(model.law, spec.surface, spec.robot.pre_pressure, area)
    adaptation, replanning = compose(name, LEGS, replanner)
    return FeedForward(
        chain=model.chain,
        mass=robot_mass(spec.robot),
        inertia=climber.trunk_inertia,
        com_height=float(model.chain.hip[1]),
        pads=Pads(*(np.full(LEGS, v) for v in (model.law.friction, adhesion, pull_off))),
        detector=SlipDetector(threshold=spec.climb.slip_threshold, hold=spec.climb.slip_hold),
        adaptation=adaptation,
        replanning=replanning,
    )


def pull_off_of(law: BondLaw, surface: config.Surface, preload: float, area: float) -> float:
    """The most a pad pressed with ``preload`` holds pulled straight off the wall, N: its bonds'
    normal strength, s sigma A, with s the preload factor as in adhesion_truth. The cone's shift
    F_adh / mu = s tau_max A / mu is k / mu times it (acrylic: 34.7 N against 10.4 N). A film pulled
    at its heel peels below s sigma A (Kendall's steady peel at 90 degrees, b G, is 1.5 N on
    acrylic), but the pads hold more than that: a stance fore pad carries 1.9-2.5 N for seconds
    (the trunk's moment on a lone fore foot) and a whole-bonded one 8.3 N at its partner's
    landing (issue 40), so b G would refuse the statics of every three-foot stance."""
    return float(law.preload_factor(preload / area)) * surface.strength * area


def control_counts(control: FeedForward | None, replanner: Replanner) -> dict[str, int]:
    """What the controller did (none: {}), with the CoM re-planner's refusals where it is one."""
    if control is None:
        return {}
    counts = asdict(control.counts)
    if isinstance(replanner, PlannerReplanner):
        counts["replan_infeasible"] = replanner.counts.infeasible
        counts["replan_outside"] = replanner.counts.outside
    return counts


def climb(
    spec: ClimbSpec, duration: float | None = None, replanner: Replanner | None = None
) -> ClimbRun:
    """Run one climb (``duration``: stop early, for tests and benchmarks; ``replanner``: the
    body's re-planner of the replan and both controllers, by default the one-step CoM planner's,
    :class:`~ftfof.climb.control.com_replan.PlannerReplanner`; ``keep_plan`` keeps the gait's)."""
    exu.config.printToConsole = False
    started = time.perf_counter()
    gait, chain = gait_of(spec), chain_of(spec.robot)
    law = BondLaw.from_surface(spec.surface, spec.solver.contact_smoothing)
    model: Climber = build(spec, chain, gait, law)
    solver = exu.MainSolverImplicitSecondOrder()
    rate = max(spec.climb.imu_rate_hz, spec.platform.sensor.rate_hz)
    if replanner is None:
        replanner = PlannerReplanner(gait, robot_mass(spec.robot), float(model.chain.hip[1]))
    control = controller_of(model, replanner)
    loop = ClimbLoop(model, solver, rate, control)
    model.mbs.SetPreStepUserFunction(loop)
    model.mbs.SetPostStepUserFunction(loop.after_step)
    end = gait.end if duration is None else duration
    error = ""
    try:
        solver.SolveSystem(model.mbs, solver_settings(spec.solver, end, spec.solver.step, rate))
    except exu.ExudynError as err:
        lines = str(err).strip().splitlines()
        error = f"{type(err).__name__}: {lines[-1] if lines else err}"
    if not error and loop.stopped:
        error = f"stopped early: {loop.stopped}"
    if control is not None:
        # Exudyn keeps the system, and through the loop this controller, to the interpreter's
        # end, where nanobind reports each live proxsuite QP as a leak: release it now
        control.distributor.reset()
    rows = loop.rows[: loop.count]
    channels = {name: rows[:, sl] for name, sl in channel_slices().items()}
    channels["t"] = channels["t"][:, 0]
    channels["body_plan"] = channels["body_plan"][:, 0]
    channels["swing"] = channels["swing"][:, 0].astype(int)
    return ClimbRun(
        spec=spec,
        gait=gait,
        channels=channels,
        fell=loop.fall is not None,
        fall_reason=loop.fall.why if loop.fall else "",
        error=error,
        wall_time=time.perf_counter() - started,
        steps=loop.steps,
        imu_reference=np.asarray(model.mbs.GetSensorStoredData(model.imu_sensor)),
        control=control_counts(control, replanner),
        estimates=[] if control is None else control.estimates,
    )
