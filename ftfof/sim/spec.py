"""What one simulated acquisition needs, as a picklable value (workers build the model from it).

Exudyn systems with user functions cannot be pickled (docs/simulator.md), so the pool ships
these specs and each worker builds and solves its own model.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

import ftfof.config as config
from ftfof.demand import proof_pull
from ftfof.seeds import seed_for
from ftfof.trajectory.bezier import evaluate
from ftfof.trajectory.piecewise import PiecewiseQuintic, Sampled

BASELINE_SEGMENTS = 16  # Hermite pieces for the analytic baselines (error < 1e-9 m)


@dataclass(frozen=True)
class SampleSpec:
    key: str  # unique within an acquisition: "<source>:<sample_id>"
    source: str  # sampled | baseline:<name> | optimum | front | imported | fine:<source>
    sample_id: int
    trajectory: PiecewiseQuintic  # foot motion in trajectory time [0, T3]
    landing: tuple[float, float]  # P15 - P0, where the carriage brings the sensor centre
    pad_length: float  # lf, m
    pre_pressure: float  # a, N
    mechanics: config.PlatformMechanics
    surface: config.Surface
    platform: config.Platform
    solver: config.Solver
    leg_model: str
    leg: config.PlanarLeg | config.SpatialLeg
    seed: int
    ankle_rest: float = 0.0  # the foot's rest angle in the air, rad (Robot.ankle_rest_angle)
    proof_pull: float | None = None  # F_proof, N, pulled after the landing hold; None: no pull

    @property
    def trajectory_start(self) -> float:
        p = self.platform.protocol
        return p.settle + p.press + p.press_hold

    @property
    def landing_end(self) -> float:
        """When the landing hold ends: the record's end (channels and Table I's figures)."""
        return (
            self.trajectory_start + self.trajectory.duration + self.platform.protocol.landing_hold
        )

    @property
    def end_time(self) -> float:
        """The run's end: the landing hold's, or the proof pull's after it."""
        if self.proof_pull is None:
            return self.landing_end
        p = self.platform.protocol
        return self.landing_end + p.proof_ramp + p.proof_hold


@dataclass(frozen=True)
class Bench:
    """Everything shared by the samples of one acquisition run."""

    robot: config.Robot
    surface: config.Surface
    platform: config.Platform
    acquire: config.Acquire
    seed: int  # base.seed; each sample's noise seed is its child in the acquisition stream

    def spec(self, source: str, sample_id: int, trajectory: PiecewiseQuintic) -> SampleSpec:
        r = self.robot
        return SampleSpec(
            key=f"{source}:{sample_id}",
            source=source,
            sample_id=sample_id,
            trajectory=trajectory,
            landing=(r.landing.x, r.landing.z),
            pad_length=r.foot.pad_length,
            pre_pressure=r.pre_pressure,
            mechanics=r.platform,
            surface=self.surface,
            platform=self.platform,
            solver=self.acquire.solver,
            leg_model=self.acquire.leg_model,
            leg=r.leg,
            seed=seed_for(self.seed, "acquisition", sample_id),
            ankle_rest=r.ankle_rest_angle,
            proof_pull=proof_pull(r),
        )

    def bezier(self, source: str, sample_id: int, X: np.ndarray) -> SampleSpec:
        """A three-segment quintic Bezier sample, converted exactly to a piecewise quintic."""
        r = self.robot
        t = np.array(r.timing.bounds)
        samples = evaluate(X, np.zeros(2), np.array([r.landing.x, r.landing.z]), r.timing, t)
        return self.spec(source, sample_id, PiecewiseQuintic.from_samples(samples))

    def analytic(self, source: str, sample_id: int, trajectory: Sampled) -> SampleSpec:
        """Any analytic trajectory over [0, T3] (the baselines), Hermite-fitted."""
        pq = PiecewiseQuintic.fit(trajectory, self.robot.timing.T3, BASELINE_SEGMENTS)
        return self.spec(source, sample_id, pq)


def baseline_specs(
    on: Bench, trajectories: Mapping[str, Sampled], names: Iterable[str] | None = None
) -> list[SampleSpec]:
    """One spec per baseline (``names`` in order; default all), keyed ``baseline:<name>``."""
    return [
        on.analytic(f"baseline:{n}", 0, trajectories[n])
        for n in (trajectories if names is None else names)
    ]
