"""A robot and the surface it climbs: the leg, the foot, its film and pad, the body, the timing."""

from __future__ import annotations

from typing import Annotated, Literal, get_args

import numpy as np
from pydantic import (
    AfterValidator,
    Field,
    NonNegativeFloat,
    PositiveFloat,
    model_validator,
)

from ftfof.config.common import Baseline, Fraction, Objective, Strict, _distinct


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


class Backing(Strict):
    """The compliant layer between the plate foot's rigid plate and the film (foam or
    elastomer): per film node a normal spring E A / t and a shear spring G A / t, G = E / 2(1 + nu),
    damped at ``damping_ratio`` of each node's critical damping."""

    modulus: PositiveFloat  # E, Pa
    thickness: PositiveFloat  # t, m
    poisson: Annotated[float, Field(ge=0.0, lt=0.5)]  # nu
    damping_ratio: NonNegativeFloat
    source: Annotated[str, Field(min_length=10)]  # where E and t come from

    @property
    def shear_modulus(self) -> float:
        return self.modulus / (2.0 * (1.0 + self.poisson))


class FootMechanics(Strict):
    """The foot on its passive, spring-loaded ankle (docs/simulator.md, "The foot").

    ``grip``: a rigid foot clamping the film's first ``grip_length``, the rest of the pad free
    ahead of it. ``plate``: a rigid plate the pad's length backs the whole film through a
    compliant ``backing``, hung from the leg on a passive ankle at the heel that rests toe-down
    in the air (the robot's droop hs over lf) and stops at ``ankle_range``.
    """

    model: Literal["grip", "plate"] = "grip"
    mass: PositiveFloat  # kg
    inertia: PositiveFloat  # kg m^2 about the ankle
    ankle_height: PositiveFloat  # ankle above the film, m
    grip_length: PositiveFloat  # film length clamped under the foot (grip), m
    ankle_stiffness: PositiveFloat  # N m/rad
    ankle_damping: NonNegativeFloat  # N m s/rad
    backing: Backing | None = None  # the plate foot's
    # the plate's rotation limits from flat, rad: toe down (negative), toe up; past them the
    # ankle's stop adds ``ankle_stop_stiffness`` (N m/rad)
    ankle_range: tuple[float, float] | None = None
    ankle_stop_stiffness: PositiveFloat = 500.0

    @model_validator(mode="after")
    def _plate_parts(self) -> FootMechanics:
        if self.model == "plate":
            if self.backing is None or self.ankle_range is None:
                raise ValueError("a plate foot needs foot.backing and foot.ankle_range")
            low, high = self.ankle_range
            if not low < 0.0 <= high:
                raise ValueError(f"foot.ankle_range must hold 0 (flat): got [{low}, {high}]")
        return self


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


LEG_NAMES = ("FL", "FR", "HL", "HR")  # the climbing robot's legs: fore/hind, left/right


def _a_gait(order: tuple[int, int, int, int]) -> tuple[int, int, int, int]:
    if sorted(order) != [0, 1, 2, 3]:
        raise ValueError(f"must name each leg 0-3 ({', '.join(LEG_NAMES)}) once")
    return order


class Climber(Strict):
    """The whole robot on the wall (ftfof/climb): its trunk, where the four hips sit on it, what
    its servos can give, and the order its legs swing in. Each leg is ``leg`` with the platform's
    foot, film and joint gains; the numbers here are estimates, with ``source`` saying whose."""

    trunk_mass: PositiveFloat  # kg, without legs and feet (those: platform.link_mass, foot.mass)
    trunk_inertia: PositiveFloat  # kg m^2, about the lateral axis (pitch)
    hip_spacing: PositiveFloat  # m, fore hips to hind hips; the centre of mass midway
    torque_limits: tuple[PositiveFloat, PositiveFloat, PositiveFloat]  # N m per leg joint
    # the mount between the leg's last link and the foot (MST-Q's pressing support rack), N/m;
    # None: rigid (the joints' servo gains are the leg's compliance)
    foot_mount_stiffness: XZ | None = None
    # crawl order, one leg at a time, as indices into LEG_NAMES
    gait: Annotated[tuple[int, int, int, int], AfterValidator(_a_gait)] = (2, 0, 3, 1)
    source: Annotated[str, Field(min_length=10)]  # where the estimates come from


class Proof(Strict):
    """The proof pull (issue 53): after the landing hold the platform pulls the landed pad at its
    ankle to F_proof, the robot's fore stance demand a + m g h / L times ``safety_factor``
    (:func:`ftfof.demand.proof_pull`); with ``refuse``, a landing whose pad lets a further tenth
    go first is refused."""

    safety_factor: PositiveFloat
    # whether a landing that does not hold F_proof is refused wherever the robot's rules apply
    # (False: the pull is measured and reported only)
    refuse: bool = True


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
    # The common trajectory evaluate's Table I compares against for this robot (one it can run);
    # None: evaluate.reference where the robot can run it, else the best baseline it can run.
    reference: Baseline | None = None
    # the whole robot on the wall, for `ftfof climb` and evaluate's climbs; None: it cannot climb
    climber: Climber | None = None
    # the landed pad's proof pull; None: no proof pull. It needs a climber (the demand is its)
    proof: Proof | None = None

    @property
    def ankle_rest_angle(self) -> float:
        """The plate foot's rest angle in the air, rad (negative: toe down): the droop hs over
        the pad's length, asin(hs / lf); 0 for the grip foot, whose film droops instead."""
        if self.platform.foot.model != "plate":
            return 0.0
        return -float(np.arcsin(min(self.foot.droop_height / self.foot.pad_length, 1.0)))

    @property
    def pad_area(self) -> float:
        """The pad's area on the wall, m^2: its length times the film's width."""
        return self.foot.pad_length * self.platform.film.width

    @model_validator(mode="after")
    def _a_proof_pull_needs_a_climber(self) -> Robot:
        if self.proof is not None and self.climber is None:
            raise ValueError(
                "proof: F_proof is the climbing robot's fore stance demand a + m g h / L, and this"
                " robot has no climber to take m and L from (add one, or set proof: null)"
            )
        return self

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
    area = robot.pad_area
    engaged = 1.0 - np.exp(-robot.pre_pressure / (area * surface.preload_pressure))
    weight = robot.platform.body.mass * GRAVITY
    return float(SHEAR_SAFETY_FACTOR * weight / STANCE_FEET / (surface.strength * area * engaged))
