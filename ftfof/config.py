"""Typed settings: the one schema every stage validates ``params.yaml`` against.

The models are pure (no file IO); ``ftfof.pipeline.params_file`` reads the YAML and builds them.
Every model forbids unknown keys, so a typo fails loudly with its key path instead of being
ignored.
"""

from __future__ import annotations

from typing import Annotated, Literal, get_args

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    NonNegativeFloat,
    NonNegativeInt,
    PositiveFloat,
    PositiveInt,
    model_validator,
)

Fraction = Annotated[float, Field(gt=0, le=1)]
# The allowed names: every module that needs one of these lists reads it here (typing.get_args).
# fs6 is the bending constraint; fsj the body jitter; *_normal the paper's normal-only fs1/fs2
Objective = Literal["fs1", "fs2", "fs3", "fs4", "fs5", "fs7", "fsj", "fs1_normal", "fs2_normal"]
Strategy = Literal[Objective, "fs6"]  # every strategy function (FTFOF §V.A)
Loss = Literal["dilate", "mse"]
# the surrogates' target series (ftfof.data.targets.TARGETS, in its order)
Target = Literal["pull", "Fd", "Fp", "jitter", "body_acc", "curvature", "clearance", "retouch"]
# those only ever read by their maximum, which a peak GP may set (pull and Fd: fs2 reads their
# mean; clearance: the swing gap reads its dip)
PeakTarget = Literal["Fp", "jitter", "body_acc", "curvature", "retouch"]
Baseline = Literal["polynomial", "cycloidal", "random_bezier", "eps_bezier"]
Design = Literal["sobol", "lhs"]


class Strict(BaseModel):
    """Base for every settings block: unknown keys are errors, values are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class Point(Strict):
    """A point or vector in the sagittal plane (x along the wall, z away from it), SI units."""

    x: float
    z: float


class Timing(Strict):
    """End times of the detachment, swing and adhesion segments (FTFOF eq. 2), seconds."""

    T1: PositiveFloat
    T2: PositiveFloat
    T3: PositiveFloat

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

    pad_length: PositiveFloat  # lf, m
    # fc, m: the film's tightest bend without damage, a rule every trajectory keeps (its free
    # span, measured by the simulator and predicted by the surrogate)
    film_min_bend_radius: PositiveFloat
    droop_height: NonNegativeFloat  # hs, m
    # the whole pad rises at least this far above the wall in the swing (the film's lowest point
    # on the platform), or it scuffs along the wall and lands while the foot still moves, m
    swing_clearance: PositiveFloat


class MinDetachment(Strict):
    """Minimum detachment point md = (ld along x, hd along z), metres (FTFOF §III.B.3)."""

    ld: NonNegativeFloat
    hd: PositiveFloat


class Limit(Strict):
    """A foot position or velocity limit: derived from the leg (eq. 7-8) or pinned by the preset.

    ``pinned`` is the final value, after the safety factor; without it the leg model is searched.
    """

    safety_factor: Fraction
    pinned: Point | None = None


def _increasing(pair: tuple[float, float]) -> tuple[float, float]:
    if not pair[0] < pair[1]:
        raise ValueError("must be an increasing pair [low, high]")
    return pair


JointRange = Annotated[tuple[float, float], AfterValidator(_increasing)]


class PlanarLeg(Strict):
    """Planar hip-knee-ankle leg; the ankle keeps the foot plate parallel to the wall."""

    type: Literal["planar3"]
    hip: Point  # hip joint in the trajectory frame (origin P0), m
    links: tuple[PositiveFloat, PositiveFloat]  # thigh, shank, m
    foot_offset: Point  # pad contact point relative to the ankle, m
    joint_limits: tuple[JointRange, JointRange, JointRange]  # rad
    joint_speed_limits: tuple[PositiveFloat, PositiveFloat, PositiveFloat]  # rad/s


class SpatialLeg(Strict):
    """3-DOF leg of the ε-Bezier paper (D-H table I, eq. 5-6); the trajectory lies in y = 0."""

    type: Literal["spatial3"]
    hip: Point  # origin of the D-H chain {O_1} in the trajectory frame, m
    lateral_offset: float = 0.0  # y0, m
    d: tuple[PositiveFloat, PositiveFloat, PositiveFloat, NonNegativeFloat]  # d1, d2, d3, d4, m
    joint_limits: tuple[JointRange, JointRange, JointRange]
    joint_speed_limits: tuple[PositiveFloat, PositiveFloat, PositiveFloat]


LegModel = PlanarLeg | SpatialLeg
Leg = Annotated[LegModel, Field(discriminator="type")]
# The discriminator tags, read from the models themselves.
LEG_TYPES: tuple[str, ...] = tuple(
    get_args(m.model_fields["type"].annotation)[0] for m in get_args(LegModel)
)


class Shape(Strict):
    """Trajectory shape rules (FTFOF eq. 18-22) chosen per foot structure."""

    detachment: Literal["upper_triangle", "vertical"]
    adhesion: Literal["arc_from_right", "vertical_press"]
    complete_detachment: Literal["peel", "vertical"]
    press_depth: NonNegativeFloat = 0.0  # how far the adhesion segment may go into the wall, m


class PathRules(Strict):
    """Rules on the whole sampled trajectory (FTFOF §III.B.3, eq. 15), switched per robot."""

    md_path: bool  # detachment keeps z >= hd once x >= ld, on the path, not only at P5
    min_path_radius: PositiveFloat  # m, tightest bend of the foot's path (fs6's hairpin guard)


class XZ(Strict):
    """A pair of values along x (the wall) and z (its normal)."""

    x: PositiveFloat
    z: PositiveFloat


class FilmMechanics(Strict):
    """The PET film with its adhesive layer, as the simulator's ANCF cable (docs/simulator.md).

    The stiffness follows from the material and the thickness, in this one place: the adhesive
    foam adds mass, not stiffness, and a film is only as thick as its fc lets it be (the robot's
    check: its outer fibre t / 2 fc stays within the yield strain).
    """

    width: PositiveFloat  # b, m
    thickness: PositiveFloat  # t, m (the PET backing)
    youngs_modulus: PositiveFloat  # E, Pa
    yield_strain: Fraction  # the outer fibre's strain at yield: a bend past it stays
    material_source: Annotated[str, Field(min_length=10)]  # where E and the yield come from
    mass_per_length: PositiveFloat  # kg/m, film + adhesive
    bending_damping: NonNegativeFloat  # N m^2 s
    axial_damping: NonNegativeFloat  # N s
    stop_radius: PositiveFloat  # m: bent tighter, the film's bending moment stiffens
    stop_stiffness: NonNegativeFloat  # how many times EI the moment rises past the stop

    @property
    def bending_stiffness(self) -> float:
        """EI = E b t^3 / 12, N m^2."""
        return self.youngs_modulus * self.width * self.thickness**3 / 12.0

    @property
    def axial_stiffness(self) -> float:
        """EA = E b t, N."""
        return self.youngs_modulus * self.width * self.thickness

    def yield_radius(self) -> float:
        """The tightest bend the film takes without permanent deformation: t / (2 yield strain)."""
        return self.thickness / (2.0 * self.yield_strain)


class FootMechanics(Strict):
    """Rigid foot on a passive, spring-loaded ankle holding the film's near end."""

    mass: PositiveFloat  # kg
    inertia: PositiveFloat  # kg m^2 about the ankle
    ankle_height: PositiveFloat  # ankle above the film, m
    grip_length: PositiveFloat  # film length clamped under the foot, m
    ankle_stiffness: PositiveFloat  # N m/rad
    ankle_damping: NonNegativeFloat  # N m s/rad


class BodyMechanics(Strict):
    """Robot body on compliant mounts (the other feet on the wall) carrying the IMU."""

    mass: PositiveFloat  # kg, the robot's mass (its weight sets the pad's least shear capacity)
    mount_stiffness: XZ  # N/m
    mount_damping: XZ  # N s/m


class PlatformMechanics(Strict):
    """How the robot's leg, foot and film behave on the acquisition platform."""

    film: FilmMechanics
    foot: FootMechanics
    leg_stiffness: XZ  # lumped leg: servo and link compliance, N/m
    leg_damping: XZ  # N s/m
    body: BodyMechanics
    joint_gains: tuple[
        PositiveFloat, PositiveFloat
    ]  # joint-level leg: PD gains (N m/rad, N m s/rad)
    link_mass: PositiveFloat  # joint-level leg: mass of each link, kg


def _distinct(names: list[str]) -> list[str]:
    if len(set(names)) != len(names):
        raise ValueError("must not repeat a name")
    return names


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
    # priority order for the RHS choice
    objectives: Annotated[list[Objective], Field(min_length=2), AfterValidator(_distinct)]
    pre_pressure: PositiveFloat  # a, N (FTFOF eq. 12)
    # the landing must press the pad to a within this fraction of a: the next stance's preload
    # (a constraint of the search and a verdict of the simulator check); None: not required
    landing_tolerance: Fraction | None = None
    # bonds formed again in the swing (after complete detachment, before T2) the search may
    # predict: 0.5 = more likely than not none (the pad_retouch constraint); None: not required
    retouch_allowed: NonNegativeFloat | None = 0.5
    # the peak body acceleration over the step (detachment and landing) the simulator check
    # allows, m/s^2 (ftfof/data/shake.py); None: not required
    body_acc_limit: PositiveFloat | None = None
    platform: PlatformMechanics
    # The paper's published optimum (12 decision values, m), simulated in `evaluate` like a
    # baseline and never fitted; null where the robot has none usable here.
    published_optimum: Annotated[list[float], Field(min_length=12, max_length=12)] | None

    @model_validator(mode="after")
    def _film_survives_its_fc(self) -> Robot:
        film, fc = self.platform.film, self.foot.film_min_bend_radius
        if film.yield_radius() > fc * (1.0 + 1e-9):  # t = 2 fc eps_y exactly is allowed
            strain = film.thickness / (2.0 * fc)
            raise ValueError(
                f"platform.film.thickness {1e6 * film.thickness:g} um bent to"
                f" foot.film_min_bend_radius {1e3 * fc:g} mm strains its outer fibre"
                f" {100 * strain:.3g} %, past platform.film.yield_strain"
                f" {100 * film.yield_strain:.3g} %: that film yields before fc (thinner than"
                f" {1e6 * 2 * fc * film.yield_strain:.0f} um survives it)"
            )
        return self


class Surface(Strict):
    """Adhesion and friction of one plate, per unit pad area (docs/simulator.md)."""

    note: str  # where the numbers come from
    strength: PositiveFloat  # sigma_max, Pa
    fracture_energy: PositiveFloat  # G_c, J/m^2
    # k = lap-shear capacity / normal pull-off of the whole pad = mode II strength tau / sigma,
    # with where k comes from (a publication or a measurement), and G_II / G_I
    shear_capacity_ratio: PositiveFloat
    shear_source: Annotated[str, Field(min_length=10)]
    shear_energy_ratio: PositiveFloat
    rate_exponent: PositiveFloat  # n in R(v) = 1 + (v / v*)^n
    rate_speed: PositiveFloat  # v*, m/s
    preload_pressure: PositiveFloat  # p* in phi = 1 - exp(-p_max / p*), Pa
    friction: NonNegativeFloat  # mu
    contact_stiffness: PositiveFloat  # Pa/m (adhesive foam in compression)
    restitution: Fraction  # Hunt-Crossley e
    rebond_pressure: PositiveFloat  # contact pressure that re-forms a broken bond, Pa


GRAVITY = 9.81  # m/s^2
STANCE_FEET = 3  # a quadruped swings one foot at a time
SHEAR_SAFETY_FACTOR = 2.0


def min_shear_capacity_ratio(robot: Robot, surface: Surface) -> float:
    """The least lap-shear / pull-off ratio k with which the stance feet hold the robot's weight.

    On a vertical wall the weight m g (m: the robot body's mass) is carried in shear by
    STANCE_FEET pads, each pressed with the pre-pressure a, so each holds
    k sigma A phi(a) >= SHEAR_SAFETY_FACTOR m g / STANCE_FEET, with A the pad area and
    phi(a) = 1 - exp(-a / (A p*)) the preload factor of the bond law.
    """
    area = robot.platform.film.width * robot.foot.pad_length
    engaged = 1.0 - np.exp(-robot.pre_pressure / (area * surface.preload_pressure))
    weight = robot.platform.body.mass * GRAVITY
    return float(SHEAR_SAFETY_FACTOR * weight / STANCE_FEET / (surface.strength * area * engaged))


class Sensor(Strict):
    """The 3-axis force sensor under the adhesion plate."""

    plate_mass: PositiveFloat  # kg
    stiffness: PositiveFloat  # N/m per axis
    damping: NonNegativeFloat  # N s/m per axis
    rate_hz: PositiveFloat  # acquisition rate
    cutoff_hz: PositiveFloat  # the sensor's low-pass (2nd-order Butterworth, causal)
    noise: NonNegativeFloat  # white noise standard deviation, N


class Protocol(Strict):
    """One acquisition: settle, press, run the trajectory, hold the landing (docs/simulator.md)."""

    settle: PositiveFloat  # s
    press: PositiveFloat  # s, ramp to the pre-pressure
    press_hold: PositiveFloat  # s
    landing_hold: PositiveFloat  # s after the trajectory ends
    switch_height: PositiveFloat  # photoelectric switch above the plate, m
    carriage_time: PositiveFloat  # linear module move, s


class Platform(Strict):
    sensor: Sensor
    protocol: Protocol


class Solver(Strict):
    """Exudyn settings (docs/simulator.md): implicit generalised-alpha with step control."""

    nodes: Annotated[int, Field(ge=4)] = 20  # bond elements along the film
    step: PositiveFloat = 5e-4  # s, while bonds break or the pad lands
    # s, elsewhere: the same, since a change of step shakes the body (docs/simulator.md)
    free_step: PositiveFloat = 5e-4
    tolerance: PositiveFloat = 1e-3  # Newton relative and absolute tolerance
    spectral_radius: Annotated[float, Field(ge=0, le=1)] = 0.5
    contact_smoothing: PositiveFloat = 1e-4  # m, width of the C1 contact ramp
    time_budget: PositiveFloat = 60.0  # wall seconds per sample before it is stopped as failed


class Acquire(Strict):
    workers: NonNegativeInt = 0  # 0 = all cores
    scheduler: str | None = None  # Dask scheduler address, e.g. tcp://127.0.0.1:8786
    batch: PositiveInt = 8  # samples per task
    max_failure_rate: Annotated[float, Field(ge=0, le=1)] = 0.05
    leg_model: Literal["lumped", "joints"] = "lumped"
    baselines: bool = True
    solver: Solver = Solver()


class Dataset(Strict):
    """How acquisitions become fixed-length training sequences (docs/simulator.md, Dataset)."""

    seq_len: Annotated[int, Field(ge=8)] = 128
    hold: NonNegativeFloat = 0.1  # s of the landing hold after T3 kept in each sequence
    validation_fraction: Annotated[float, Field(gt=0, lt=1)] = 0.15
    plot_samples: PositiveInt = 4


class Train(Strict):
    """Multi-output GRU surrogates, trained with DILATE and/or MSE (FTFOF §IV.B;
    docs/surrogates.md)."""

    hidden: PositiveInt = 64
    layers: PositiveInt = 2
    dropout: Annotated[float, Field(ge=0, lt=1)] = 0.0
    epochs: PositiveInt = 60
    batch: PositiveInt = 32
    lr: PositiveFloat = 3e-3
    weight_decay: NonNegativeFloat = 0.0
    patience: PositiveInt = 10  # early stopping on the validation loss
    alpha: Annotated[float, Field(ge=0, le=1)] = 0.5  # DILATE shape/temporal balance
    gamma: PositiveFloat = 0.01  # soft-DTW smoothing
    losses: Annotated[list[Loss], Field(min_length=1)] = ["dilate", "mse"]
    use: Loss = "dilate"  # the model the optimiser and report use
    # MLflow registry alias train sets on the `use` model; optimize loads models:/...@alias
    alias: Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9_-]*$")] = "champion"
    threads: NonNegativeInt = 0  # torch threads per model, 0 = all cores / models
    parallel: bool = True  # train the models side by side, one process each
    # targets whose peak a GP predicts from the 12 control values (ftfof/surrogate/peaks.py);
    # the series keeps the GRU's shape, scaled to the GP's peak. fs3's landing press and fs7's
    # total: the GP's validation error is a third and a half of the GRU's (docs/surrogates.md)
    peaks: Annotated[list[PeakTarget], AfterValidator(_distinct)] = ["Fp", "jitter"]

    @model_validator(mode="after")
    def _use_is_trained(self) -> Train:
        if self.use not in self.losses:
            raise ValueError(f"use {self.use!r} must be one of losses {self.losses}")
        return self


class Optimize(Strict):
    """NSGA-II on the surrogates and the RHS choice (FTFOF §V.B-C); paper defaults."""

    population: Annotated[int, Field(ge=4)] = 200
    generations: PositiveInt = 2000
    seeded_start: bool = True  # initial population from feasible Sobol draws, not uniform
    crossover_eta: PositiveFloat = 15.0  # SBX distribution index
    crossover_prob: Fraction = 0.9
    mutation_eta: PositiveFloat = 20.0  # polynomial mutation distribution index
    log_every: PositiveInt = 10  # generations between hypervolume records
    recheck_samples: Annotated[int, Field(ge=16)] = 4096  # independent feasibility grid
    rhs_alpha: Fraction = 0.9  # Algorithm 1 (the paper's alpha0): fraction of each range kept
    rhs_beta: Annotated[float, Field(gt=0, lt=1)] = 0.9  # Algorithm 1: shrink factor
    verify_candidates: NonNegativeInt = 16  # RHS candidates simulated, then chosen on; 0 = trust
    # each candidate is also simulated this many times with every free control value off by a
    # normal error of ``verify_repeatability`` (m; not kept in the box): it must pass every time,
    # and RHS chooses on the mean, its differences within the standard error ties
    verify_copies: NonNegativeInt = 2
    verify_repeatability: PositiveFloat = 2e-4
    # when every candidate of a batch is refused, the next ``verify_candidates`` in RHS order are
    # simulated, up to this many batches in all
    verify_batches: PositiveInt = 4


class RefineTarget(Strict):
    """What ends the refinement early: fidelity on the robot's first-priority objective, and a
    front the simulator passes (a front of exploits the surrogate has not seen ranks fs1 well
    and still cannot be run)."""

    spearman: Annotated[float, Field(ge=-1, le=1)] = 0.9  # rank correlation over a round's points
    relative_error: PositiveFloat = 0.15  # median over the points and at the optimum itself
    clean: Annotated[float, Field(ge=0, le=1)] = 0.9  # fraction of the points a real foot could run


class Refine(Strict):
    """Simulate where the optimiser went, grow the dataset there, fine-tune and search again."""

    rounds: NonNegativeInt = 3  # 0: evaluate gets the optimize stage's models and optimum
    points: NonNegativeInt = 50  # front members re-simulated per round, besides the optimum
    target: RefineTarget = RefineTarget()
    epochs: PositiveInt = 15  # fine-tuning epochs per round, warm-started from the last weights
    patience: PositiveInt = 4  # early stopping on validation, grown by the rounds' held-out rows
    lr: PositiveFloat = 1e-3  # fine-tuning learning rate
    generations: PositiveInt = 300  # NSGA-II generations per round, from the previous front
    # the rounds' clean simulated points (their simulated pull / jitter layers, in RHS order)
    # that join each round's simulator check beside the surrogate's candidates (0: none)
    nominate: NonNegativeInt = 8
    # targets whose peak gets a local GP on the rounds' points, taken where it knows the
    # trajectory, the broad GP of train.peaks (or, without one, the GRU's maximum) elsewhere
    # (ftfof/surrogate/peaks.py NearFront)
    near_front_peaks: Annotated[list[PeakTarget], AfterValidator(_distinct)] = ["Fp"]


class Polish(Strict):
    """NSGA-II on the simulator, from the candidates the last check passed (optimize/polish.py)."""

    generations: NonNegativeInt = 16  # 0: evaluate gets refine's optimum as it is
    population: Annotated[int, Field(ge=4)] = 24  # trajectories per generation
    # how many of the robot's objectives, in priority order, the simulator's NSGA-II weighs; the
    # choice among its result is RHS on all of them, as measured
    priorities: PositiveInt = 2
    spread: PositiveFloat = 1e-3  # m: the error of the copies that fill a short first population
    # fresh perturbed copies each polished trajectory is simulated with again before RHS chooses
    # (on these runs): the search chose among fixed draws, which flatters its best
    confirm_copies: PositiveInt = 4


class Evaluate(Strict):
    """Re-simulation of the optimum against the baselines, and the controller export."""

    front_points: NonNegativeInt = 20  # front members re-simulated for fidelity
    export_rate_hz: Annotated[float, Field(gt=0, le=100_000)] = 500.0  # controller CSV rate
    reference: Baseline = "polynomial"
    # s: Table I's trajectories are simulated again with this solver step (null: not), to show
    # whether the answer holds where the acquisition step does not resolve it (docs/simulator.md)
    check_step: PositiveFloat | None = 1.25e-4
    # film elements: the optimum, the front members and Table I's trajectories are simulated
    # again on this many, to show the film's bend converged where fc is judged (null: not)
    check_nodes: Annotated[int, Field(ge=4)] | None = 80


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
    seed: NonNegativeInt  # every random stream: sampling, acquisition noise, split, ...
    # seeds the chain from train on (initialisation, shuffling, NSGA-II) when set: sweeping it
    # re-runs train -> optimize -> evaluate on the same data (null: base.seed)
    search_seed: NonNegativeInt | None = None


class Feasibility(Strict):
    """How the sampled trajectory is checked (FTFOF §III.B; docs/pipeline.md)."""

    n_t: Annotated[int, Field(ge=16)] = 256  # time samples over [0, T3]
    position_tolerance: NonNegativeFloat = 1e-6  # m
    bend_tolerance: NonNegativeFloat = 1e-9  # rad, fs6 <= this counts as 0
    min_step: PositiveFloat = 1e-9  # m, displacements shorter than this are skipped by fs6
    # accepted samples are checked again on a grid at least this fine (a controller's rate)
    recheck_hz: PositiveFloat = 1000.0


class Sample(Strict):
    n: PositiveInt
    design: Design = "sobol"
    batch: Annotated[int, Field(ge=16)] = 4096
    max_draws: Annotated[int, Field(ge=16)] = 4_000_000


class EpsBezier(Strict):
    """ε-Bezier baseline (ε-Bezier paper §III): obstacle box and the sigmoid truncation ε."""

    epsilon: PositiveFloat
    obstacle_x: tuple[float, float]  # x of the obstacle's top corners O1, O2, m
    obstacle_height: PositiveFloat  # m
    clearance: NonNegativeFloat = 0.1  # relative margin of the peak over the obstacle point O_p


class Baselines(Strict):
    """Common trajectories from P0 to P15 in the same total time (FTFOF §VI.D)."""

    lift_height: PositiveFloat  # polynomial and cycloid apex, m
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
    refine: Refine = Refine()
    polish: Polish = Polish()
    evaluate: Evaluate = Evaluate()

    @model_validator(mode="after")
    def _selected_presets_exist(self) -> Params:
        # The message names its key: an error of the whole model has no location of its own.
        for key, presets in (("robot", self.robots), ("surface", self.surfaces)):
            name = getattr(self, key)
            if name not in presets:
                raise ValueError(f"{key}: {name!r} is not a preset (have {', '.join(presets)})")
        return self

    @model_validator(mode="after")
    def _polish_weighs_objectives_the_robot_has(self) -> Params:
        have = self.selected_robot.objectives
        if self.polish.priorities > len(have):
            raise ValueError(
                f"polish.priorities: {self.polish.priorities} is more than robot {self.robot!r}'s "
                f"{len(have)} objectives ({', '.join(have)})"
            )
        return self

    @model_validator(mode="after")
    def _the_dataset_sees_the_whole_landing_hold(self) -> Params:
        # fs3 is the landing pre-pressure: a base that ends inside the hold would miss its peak
        hold = self.platform.protocol.landing_hold
        if self.dataset.hold < hold:
            raise ValueError(
                f"dataset.hold: {self.dataset.hold:g} s ends inside the landing hold "
                f"(platform.protocol.landing_hold {hold:g} s); fs3 needs all of it"
            )
        return self

    @model_validator(mode="after")
    def _the_check_step_is_finer(self) -> Params:
        check, step = self.evaluate.check_step, self.acquire.solver.step
        if check is not None and check >= step:
            raise ValueError(
                f"evaluate.check_step: {check:g} s is not finer than acquire.solver.step "
                f"({step:g} s); it checks the answer at a smaller step (null: no check)"
            )
        return self

    @model_validator(mode="after")
    def _the_check_film_is_finer(self) -> Params:
        check, nodes = self.evaluate.check_nodes, self.acquire.solver.nodes
        if check is not None and check <= nodes:
            raise ValueError(
                f"evaluate.check_nodes: {check} film elements are not finer than"
                f" acquire.solver.nodes ({nodes}); it checks the film's bend on a finer film"
                " (null: no check)"
            )
        return self

    @model_validator(mode="after")
    def _pad_holds_the_robot_in_shear(self) -> Params:
        k_min = min_shear_capacity_ratio(self.selected_robot, self.selected_surface)
        k = self.selected_surface.shear_capacity_ratio
        if k < k_min:
            raise ValueError(
                f"surfaces.{self.surface}.shear_capacity_ratio: {k:g} is below {k_min:.3g}, the"
                f" ratio at which three feet of robot {self.robot!r}, each pressed with its"
                " pre-pressure, hold its weight on a vertical wall with safety factor"
                f" {SHEAR_SAFETY_FACTOR:g}"
            )
        return self

    @property
    def search_seed(self) -> int:
        """The seed of the surrogate training and the search (``base.search_seed`` or ``seed``)."""
        base = self.base
        return base.seed if base.search_seed is None else base.search_seed

    @property
    def selected_robot(self) -> Robot:
        return self.robots[self.robot]

    @property
    def selected_surface(self) -> Surface:
        return self.surfaces[self.surface]
