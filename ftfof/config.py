"""Typed settings: the one schema every stage validates ``params.yaml`` against.

The models are pure (no file IO); ``stages.params`` reads the YAML and builds them. Every model
forbids unknown keys, so a typo fails loudly with its key path instead of being ignored.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, field_validator, model_validator

Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Fraction = Annotated[float, Field(gt=0, le=1)]
Objective = Literal["fs1", "fs2", "fs3", "fs4", "fs5", "fs6", "fs7"]


class Strict(BaseModel):
    """Base for every settings block: unknown keys are errors, values are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class Point(Strict):
    """A point or vector in the sagittal plane (x along the wall, z away from it), SI units."""

    x: float
    z: float


class Timing(Strict):
    """End times of the detachment, swing and adhesion segments (FTFOF eq. 2), seconds."""

    T1: Positive
    T2: Positive
    T3: Positive

    @model_validator(mode="after")
    def _ordered(self) -> Timing:
        if not self.T1 < self.T2 < self.T3:
            raise ValueError(f"must satisfy T1 < T2 < T3 (got {self.T1}, {self.T2}, {self.T3})")
        return self

    @property
    def durations(self) -> tuple[float, float, float]:
        return (self.T1, self.T2 - self.T1, self.T3 - self.T2)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        return (0.0, self.T1, self.T2, self.T3)

    def grid(self, n: int) -> np.ndarray:
        """``n`` equally spaced times over [0, T3], both ends included."""
        return np.linspace(0.0, self.T3, n)


class Foot(Strict):
    """Pad geometry that shapes the constraint policy (FTFOF §VI.A, Fig. 6-7)."""

    pad_length: Positive  # lf, m
    film_min_bend_radius: Positive  # fc, m
    droop_height: NonNegative  # hs, m


class MinDetachment(Strict):
    """Minimum detachment point md = (ld along x, hd along z), metres (FTFOF §III.B.3)."""

    ld: NonNegative
    hd: Positive


class Limit(Strict):
    """A foot position or velocity limit: derived from the leg (eq. 7-8) or pinned by the preset.

    ``pinned`` is the final value, after the safety factor; without it the leg model is searched.
    """

    safety_factor: Fraction
    pinned: Point | None = None


JointRange = tuple[float, float]


class PlanarLeg(Strict):
    """Planar hip-knee-ankle leg; the ankle keeps the foot plate parallel to the wall."""

    type: Literal["planar3"]
    hip: Point  # hip joint in the trajectory frame (origin P0), m
    links: tuple[Positive, Positive]  # thigh, shank, m
    foot_offset: Point  # pad contact point relative to the ankle, m
    joint_limits: tuple[JointRange, JointRange, JointRange]  # rad
    joint_speed_limits: tuple[Positive, Positive, Positive]  # rad/s

    @model_validator(mode="after")
    def _ranges(self) -> PlanarLeg:
        _check_ranges(self.joint_limits)
        return self


class SpatialLeg(Strict):
    """3-DOF leg of eps_bezier.txt (D-H table I, eq. 5-6); the trajectory lies in y = 0."""

    type: Literal["spatial3"]
    hip: Point  # origin of the D-H chain {O_1} in the trajectory frame, m
    lateral_offset: float = 0.0  # y0, m
    d: tuple[Positive, Positive, Positive, NonNegative]  # d1, d2, d3, d4, m
    joint_limits: tuple[JointRange, JointRange, JointRange]
    joint_speed_limits: tuple[Positive, Positive, Positive]

    @model_validator(mode="after")
    def _ranges(self) -> SpatialLeg:
        _check_ranges(self.joint_limits)
        return self


def _check_ranges(ranges: tuple[JointRange, ...]) -> None:
    for i, (lo, hi) in enumerate(ranges):
        if not lo < hi:
            raise ValueError(f"joint {i + 1} limit must be an increasing pair (got [{lo}, {hi}])")


Leg = Annotated[PlanarLeg | SpatialLeg, Field(discriminator="type")]


class Shape(Strict):
    """Trajectory shape rules (FTFOF eq. 18-22) chosen per foot structure."""

    detachment: Literal["upper_triangle", "vertical"]
    adhesion: Literal["arc_from_right", "vertical_press"]
    complete_detachment: Literal["peel", "vertical"]
    press_depth: NonNegative = 0.0  # how far the adhesion segment may go into the wall, m


class PathRules(Strict):
    """Rules on the whole sampled trajectory (FTFOF §III.B.3, eq. 15), switched per robot."""

    md_path: bool  # detachment keeps z >= hd once x >= ld, on the path, not only at P5
    min_path_radius: Positive  # m, tightest bend of the foot's path (fs6's hairpin guard)


class XZ(Strict):
    """A pair of values along x (the wall) and z (its normal)."""

    x: Positive
    z: Positive


class FilmMechanics(Strict):
    """The PET film with its adhesive layer, as the simulator's ANCF cable (DESIGN §6)."""

    width: Positive  # b, m
    bending_stiffness: Positive  # EI, N m^2 (PET: E b h^3 / 12)
    axial_stiffness: Positive  # EA, N
    mass_per_length: Positive  # kg/m, film + adhesive
    bending_damping: NonNegative  # N m^2 s
    axial_damping: NonNegative  # N s


class FootMechanics(Strict):
    """Rigid foot on a passive, spring-loaded ankle holding the film's near end."""

    mass: Positive  # kg
    inertia: Positive  # kg m^2 about the ankle
    ankle_height: Positive  # ankle above the film, m
    grip_length: Positive  # film length clamped under the foot, m
    ankle_stiffness: Positive  # N m/rad
    ankle_damping: NonNegative  # N m s/rad


class BodyMechanics(Strict):
    """Robot body on compliant mounts (the other feet on the wall) carrying the IMU."""

    mass: Positive
    mount_stiffness: XZ  # N/m
    mount_damping: XZ  # N s/m


class PlatformMechanics(Strict):
    """How the robot's leg, foot and film behave on the acquisition platform."""

    film: FilmMechanics
    foot: FootMechanics
    leg_stiffness: XZ  # lumped leg: servo and link compliance, N/m
    leg_damping: XZ  # N s/m
    body: BodyMechanics
    joint_gains: tuple[Positive, Positive]  # joint-level leg: PD gains (N m/rad, N m s/rad)
    link_mass: Positive  # joint-level leg: mass of each link, kg


class Robot(Strict):
    """Everything that describes one robot's leg and foot for the pipeline."""

    description: str = ""
    landing: Point  # P15 relative to P0, m
    timing: Timing
    foot: Foot
    min_detachment: MinDetachment
    leg: Leg
    position_limit: Limit
    velocity_limit: Limit
    shape: Shape
    constraints: PathRules
    objectives: Annotated[list[Objective], Field(min_length=2)]  # priority order for RHS
    pre_pressure: Positive  # a, N (FTFOF eq. 12)
    platform: PlatformMechanics

    @model_validator(mode="after")
    def _objectives_unique(self) -> Robot:
        if len(set(self.objectives)) != len(self.objectives):
            raise ValueError(f"objectives must not repeat (got {self.objectives})")
        if "fs6" in self.objectives:
            raise ValueError("fs6 is the bending constraint, not an objective")
        return self


class Surface(Strict):
    """Adhesive and friction behaviour of one adhesion plate (DESIGN §6), per unit pad area."""

    note: str  # where the numbers come from
    strength: Positive  # sigma_max, Pa
    fracture_energy: Positive  # G_c, J/m^2
    shear_ratio: Positive  # shear strength / normal strength (equal critical separations)
    rate_exponent: Positive  # n in R(v) = 1 + (v / v*)^n
    rate_speed: Positive  # v*, m/s
    preload_pressure: Positive  # p* in phi = 1 - exp(-p_max / p*), Pa
    friction: NonNegative  # mu
    contact_stiffness: Positive  # Pa/m (adhesive foam in compression)
    restitution: Annotated[float, Field(gt=0, le=1)]  # Hunt-Crossley e
    rebond_pressure: Positive  # contact pressure that re-forms a broken bond, Pa


class Sensor(Strict):
    """The 3-axis force sensor under the adhesion plate."""

    plate_mass: Positive  # kg
    stiffness: Positive  # N/m per axis
    damping: NonNegative  # N s/m per axis
    rate_hz: Positive  # acquisition rate
    cutoff_hz: Positive  # the sensor's low-pass (2nd-order Butterworth, causal)
    noise: NonNegative  # white noise standard deviation, N


class Protocol(Strict):
    """One acquisition: settle, press to a, run the trajectory, hold the landing (DESIGN §6)."""

    settle: Positive  # s
    press: Positive  # s, ramp to the pre-pressure
    press_hold: Positive  # s
    landing_hold: Positive  # s after the trajectory ends
    switch_height: Positive  # photoelectric switch above the plate, m
    carriage_time: Positive  # linear module move, s


class Platform(Strict):
    sensor: Sensor
    protocol: Protocol


class Solver(Strict):
    """Exudyn settings (notes/exudyn.md): implicit generalised-alpha with step control."""

    nodes: Annotated[int, Field(ge=4)] = 20  # bond elements along the film
    step: Positive = 5e-4  # s, while bonds break or the pad lands
    free_step: Positive = 2e-3  # s, elsewhere
    tolerance: Positive = 1e-3  # Newton relative and absolute tolerance
    spectral_radius: Annotated[float, Field(ge=0, le=1)] = 0.5
    contact_smoothing: Positive = 1e-4  # m, width of the C1 contact ramp
    time_budget: Positive = 60.0  # wall seconds per sample before it is stopped as failed


class Acquire(Strict):
    workers: Annotated[int, Field(ge=0)] = 0  # 0 = all cores
    scheduler: str | None = None  # Dask scheduler address, e.g. tcp://127.0.0.1:8786
    batch: Annotated[int, Field(ge=1)] = 8  # samples per task
    max_failure_rate: Annotated[float, Field(ge=0, le=1)] = 0.05
    leg_model: Literal["lumped", "joints"] = "lumped"
    baselines: bool = True
    solver: Solver = Solver()


class Dataset(Strict):
    """How acquisitions become fixed-length training sequences (DESIGN §7)."""

    seq_len: Annotated[int, Field(ge=8)] = 128
    hold: NonNegative = 0.1  # s of the landing hold after T3 kept in each sequence
    validation_fraction: Annotated[float, Field(gt=0, lt=1)] = 0.15
    plot_samples: Annotated[int, Field(ge=1)] = 4


class Train(Strict):
    """GRU surrogates trained with DILATE and, for comparison, MSE (DESIGN §8)."""

    hidden: Annotated[int, Field(ge=1)] = 64
    layers: Annotated[int, Field(ge=1)] = 2
    dropout: Annotated[float, Field(ge=0, lt=1)] = 0.0
    epochs: Annotated[int, Field(ge=1)] = 60
    batch: Annotated[int, Field(ge=1)] = 32
    lr: Positive = 3e-3
    weight_decay: NonNegative = 0.0
    patience: Annotated[int, Field(ge=1)] = 10  # early stopping on the validation loss
    alpha: Annotated[float, Field(ge=0, le=1)] = 0.5  # DILATE shape/temporal balance
    gamma: Positive = 0.01  # soft-DTW smoothing
    losses: Annotated[list[Literal["dilate", "mse"]], Field(min_length=1)] = ["dilate", "mse"]
    use: Literal["dilate", "mse"] = "dilate"  # the models the optimiser and report use
    # MLflow registry alias train sets on the `use` pair; optimize loads models:/...@alias
    alias: Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9_-]*$")] = "champion"
    threads: Annotated[int, Field(ge=0)] = 0  # torch threads per model, 0 = all cores / models
    parallel: bool = True  # train the models side by side, one process each


class Optimize(Strict):
    """NSGA-II on the surrogates and the RHS choice (FTFOF §V.B-C, DESIGN §10); paper defaults."""

    population: Annotated[int, Field(ge=4)] = 200
    generations: Annotated[int, Field(ge=1)] = 2000
    seeded_start: bool = True  # initial population from feasible Sobol draws, not uniform
    crossover_eta: Positive = 15.0  # SBX distribution index
    crossover_prob: Fraction = 0.9
    mutation_eta: Positive = 20.0  # polynomial mutation distribution index
    log_every: Annotated[int, Field(ge=1)] = 10  # generations between hypervolume records
    recheck_samples: Annotated[int, Field(ge=16)] = 4096  # independent feasibility grid
    rhs_alpha: Fraction = 0.9  # Algorithm 1: initial fraction of each objective's range
    rhs_beta: Annotated[float, Field(gt=0, lt=1)] = 0.9  # Algorithm 1: shrink factor


class Evaluate(Strict):
    """Re-simulation of the optimum against the baselines, and the controller export (§11)."""

    front_points: Annotated[int, Field(ge=0)] = 20  # front members re-simulated for fidelity
    export_rate_hz: Annotated[float, Field(gt=0, le=100_000)] = 500.0  # controller CSV rate
    reference: Literal["polynomial", "cycloidal", "random_bezier", "eps_bezier"] = "polynomial"


class LogColumns(Strict):
    time: str = "t"
    x: str = "x"
    z: str = "z"
    Fz: str = "Fz"
    Fx: str | None = "Fx"  # optional


class LogUnits(Strict):
    time: Literal["s", "ms"] = "s"
    length: Literal["m", "mm", "um"] = "mm"
    force: Literal["N", "mN"] = "N"


class Logs(Strict):
    """The format of force logs from a physical platform (`ftfof import-logs`)."""

    columns: LogColumns = LogColumns()
    units: LogUnits = LogUnits()
    tension_positive: bool = True  # sign of Fz: detachment (pulling the plate up) positive
    surface: str = "imported"  # label stored with the imported samples


class Base(Strict):
    seed: Annotated[int, Field(ge=0)]


class Feasibility(Strict):
    """How the sampled trajectory is checked (DESIGN §4)."""

    n_t: Annotated[int, Field(ge=16)] = 256  # time samples over [0, T3]
    position_tolerance: NonNegative = 1e-6  # m
    bend_tolerance: NonNegative = 1e-9  # rad, fs6 <= this counts as 0
    min_step: Positive = 1e-9  # m, displacements shorter than this are skipped by fs6
    # accepted samples are checked again on a grid at least this fine (a controller's rate)
    recheck_hz: Positive = 1000.0


class Sample(Strict):
    n: Annotated[int, Field(ge=1)]
    design: Literal["sobol", "lhs"] = "sobol"
    batch: Annotated[int, Field(ge=16)] = 4096
    max_draws: Annotated[int, Field(ge=16)] = 4_000_000


class EpsBezier(Strict):
    """ε-Bezier baseline (eps_bezier.txt §III): obstacle box and the sigmoid truncation ε."""

    epsilon: Positive
    obstacle_x: tuple[float, float]  # x of the obstacle's top corners O1, O2, m
    obstacle_height: Positive  # m
    clearance: NonNegative = 0.1  # relative margin of the peak over the obstacle point O_p


class Baselines(Strict):
    """Common trajectories from P0 to P15 in the same total time (DESIGN §11)."""

    lift_height: Positive  # polynomial and cycloid apex, m
    eps_bezier: EpsBezier


class Params(Strict):
    """The whole ``params.yaml``."""

    base: Base
    robots: dict[str, Robot]
    robot: str
    surfaces: dict[str, Surface]
    surface: str
    platform: Platform
    feasibility: Feasibility = Feasibility()
    baselines: Baselines
    sample: Sample
    acquire: Acquire
    dataset: Dataset = Dataset()
    logs: Logs = Logs()
    train: Train = Train()
    optimize: Optimize = Optimize()
    evaluate: Evaluate = Evaluate()

    @field_validator("robot")
    @classmethod
    def _selected_exists(cls, name: str, info: ValidationInfo) -> str:
        return _preset_name(name, info.data.get("robots"))

    @field_validator("surface")
    @classmethod
    def _surface_exists(cls, name: str, info: ValidationInfo) -> str:
        return _preset_name(name, info.data.get("surfaces"))

    @property
    def selected_robot(self) -> Robot:
        return self.robots[self.robot]

    @property
    def selected_surface(self) -> Surface:
        return self.surfaces[self.surface]


def _preset_name(name: str, presets: dict | None) -> str:
    if presets is not None and name not in presets:
        raise ValueError(f"{name!r} is not a preset (have {', '.join(sorted(presets))})")
    return name
