"""The settings of each stage: the platform and its protocol, and the pipeline's stages."""

from __future__ import annotations

from typing import Annotated, Literal, get_args

from pydantic import (
    AfterValidator,
    Field,
    NonNegativeFloat,
    NonNegativeInt,
    PositiveFloat,
    PositiveInt,
    model_validator,
)

from ftfof.config.common import Baseline, Design, Fraction, Loss, PeakTarget, Strict, _distinct


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
    # the proof pull after the landing hold (robots' ``proof``): the press loop moves the sensor
    # from the held press to the pull over ``proof_ramp`` and holds it ``proof_hold``
    proof_ramp: PositiveFloat = 0.2  # s
    proof_hold: PositiveFloat = 0.5  # s


class Platform(Strict):
    sensor: Sensor
    protocol: Protocol


# the phases of a run that may take a longer step (``Solver.phase_steps``), in the protocol's
# order: before the trajectory, the settle, the press ramp and its hold; in the trajectory, the
# flight clear of the plate (no bond, from the switch + 70 ms); after it, the landing hold from
# its 50th ms on
LongPhase = Literal["settle", "press", "press_hold", "flight", "landing_hold"]
LONG_PHASES: tuple[LongPhase, ...] = get_args(LongPhase)


class Solver(Strict):
    """Exudyn settings (docs/simulator.md): implicit generalised-alpha with step control."""

    nodes: Annotated[int, Field(ge=4)] = 20  # bond elements along the film
    # m: a graded film, its elements this long over the grip, at the clamp edge and at the pad's
    # end, growing geometrically toward the pad's middle; None: uniform (docs/simulator.md,
    # "Graded film elements")
    edge_element: PositiveFloat | None = None
    step: PositiveFloat = 5e-4  # s, while bonds break or the pad lands
    # s, elsewhere: the same, since a change of step shakes the body (docs/simulator.md)
    free_step: PositiveFloat = 5e-4
    # s: a longer step in some of the protocol's phases (LongPhase -> its step), ``step`` in the
    # others and always from lift-off to the switch + 70 ms and in the landing's first 50 ms;
    # empty: ``step`` throughout. Changed between two steps, so the clock and the integrator
    # agree (docs/simulator.md, "A longer step outside the peel and the landing")
    phase_steps: dict[LongPhase, PositiveFloat] = Field(default_factory=dict)
    tolerance: PositiveFloat = 1e-3  # Newton relative and absolute tolerance
    spectral_radius: Annotated[float, Field(ge=0, le=1)] = 0.5
    contact_smoothing: PositiveFloat = 1e-4  # m, width of the C1 contact ramp
    time_budget: PositiveFloat = 60.0  # wall seconds per sample before it is stopped as failed

    @model_validator(mode="after")
    def _phase_steps_with_one_step(self) -> Solver:
        if self.phase_steps and self.free_step != self.step:
            raise ValueError("phase_steps needs free_step == step (one step outside its phases)")
        return self


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
    # each target's values above Q3 + tail_fence IQR of its training peaks are compressed
    # logarithmically before the GRU fits them (ftfof/data/tails.py); 0 = as they are
    tail_fence: NonNegativeFloat = 3.0


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
    # the search ranks each trajectory by the mean plus this many standard deviations of each
    # objective over its runs: a trajectory whose jitter swings with a 0.2 mm encoder error is
    # not one a robot can count on (0: the mean alone)
    risk_sigmas: NonNegativeFloat = 1.0


class SurfaceChange(Strict):
    """One foot's pad finds another surface mid-climb (issue 40): from ``time`` on, that pad's
    bonds follow the other preset's law (its friction and adhesion) where they hold."""

    foot: Literal["FL", "FR", "HL", "HR"]  # ftfof.config.LEG_NAMES
    time: PositiveFloat  # s into the climb; before its end (checked where the climb is built)
    surface: str  # a preset of ``surfaces``


class SlipScenario(SurfaceChange):
    """evaluate's slip comparison: one trajectory's climb with one pad's surface changed."""

    trajectory: Baseline = "eps_bezier"  # Table I's trajectory that climbs all its steps


# the highest rate a trajectory is exported at for a controller: servo loops run at 1-10 kHz, and
# a higher one only builds a file of millions of rows (`ftfof export --rate`)
EXPORT_MAX_RATE_HZ = 100_000.0


class Evaluate(Strict):
    """Re-simulation of the optimum against the baselines, and the controller export."""

    front_points: NonNegativeInt = 20  # front members re-simulated for fidelity
    # controller CSV rate
    export_rate_hz: Annotated[float, Field(gt=0, le=EXPORT_MAX_RATE_HZ)] = 500.0
    reference: Baseline = "polynomial"
    # s: Table I's trajectories are simulated again with this solver step (null: not), to show
    # whether the answer holds where the acquisition step does not resolve it (docs/simulator.md)
    check_step: PositiveFloat | None = 1.25e-4
    # film elements: the optimum, the front members and Table I's trajectories are simulated
    # again on this many, to show the film's bend converged where fc is judged (null: not)
    check_nodes: Annotated[int, Field(ge=4)] | None = 80
    # the fidelity's members simulated twice more, every control value off by
    # optimize.verify_repeatability: the rank correlation of the two runs bounds what any
    # surrogate can reach (docs/pipeline.md, "evaluate"); false: not
    repeat_front: bool = True
    # the climbing robot climbs Table I's trajectories the robot can run (docs/climb.md);
    # false, or a robot without a climber block: not
    climb: bool = True
    # the four climb.controllers on slip_scenario's climb (docs/climb.md, "Slip"): false, not
    slip_comparison: bool = False
    slip_scenario: SlipScenario = SlipScenario(foot="FL", time=4.0, surface="painted_wall")


Controller = Literal["none", "weights", "replan", "both"]


class Climb(Strict):
    """The climbing robot's run (ftfof/climb; docs/climb.md): a crawl up a vertical wall."""

    steps: PositiveInt = 8  # one swing each: 8 = two gait cycles
    shift_time: PositiveFloat = 0.5  # s, the body's advance between two swings (all feet hold)
    fall_distance: PositiveFloat = 0.02  # m, the body this far off its plan has fallen
    imu_rate_hz: PositiveFloat = 1000.0
    # the IMU: white noise (standard deviation) and a constant bias, per axis
    imu_acc_noise: NonNegativeFloat = 0.0  # m/s^2
    imu_acc_bias: float = 0.0  # m/s^2
    imu_gyro_noise: NonNegativeFloat = 0.0  # rad/s
    imu_gyro_bias: float = 0.0  # rad/s
    time_budget: PositiveFloat = 300.0  # wall seconds per climb before it is stopped as failed
    # where the optimum falls, the climb stage tries the next candidates by RHS's order, at most
    # this many, one at a time; the first that climbs is exported (docs/climb.md); 0: none
    fallbacks: NonNegativeInt = 3
    surface_change: SurfaceChange | None = None  # null: every pad on the selected surface
    # the stance feet's force control (docs/climb.md, "Slip"); null: none, the joint PD alone
    controller: Controller | None = None
    # a stance pad sliding on its patch faster than slip_threshold for slip_hold is declared
    # slipping, and the controllers answer it (climbing_slip §6.2)
    slip_threshold: PositiveFloat = 5e-3  # m/s
    slip_hold: NonNegativeFloat = 0.01  # s


def _ascending(values: list[float]) -> list[float]:
    """Distinct values, in increasing order (a sweep's axis)."""
    if len(set(values)) != len(values):
        raise ValueError(f"must not repeat a value (got {values})")
    return sorted(values)


class Payload(Strict):
    """`ftfof study payload`: the largest mass added to the trunk at which each Table I
    trajectory and the optimum still climb every step (bisection)."""

    ceiling: PositiveFloat = 0.4  # kg: the heaviest added mass tried
    resolution: PositiveFloat = 0.01  # kg: the bisection stops when the interval is this narrow

    @model_validator(mode="after")
    def _resolvable(self) -> Payload:
        if self.resolution >= self.ceiling:
            raise ValueError(f"resolution {self.resolution} kg must be below the ceiling")
        return self


class Study(Strict):
    """The studies `ftfof study` runs: the ε study (a pipeline stage) and the payload margin (a
    command of its own: it climbs each trajectory about eight times)."""

    payload: Payload = Payload()

    # the ε-Bezier baseline's truncation values (the ε-Bezier paper's Fig. 15-16; 0: plain Bezier)
    eps: Annotated[list[NonNegativeFloat], Field(min_length=2), AfterValidator(_ascending)] = [
        0.0,
        0.5,
        1.0,
        2.0,
        4.0,
        8.0,
    ]


class Identify(Strict):
    """The pipeline's identify stage: a surface's friction and adhesion from a slip log."""

    enabled: bool = True  # false: the stage records that it is off and writes nothing else
    surface: str | None = None  # the preset the log is of (null: the selected surface)
    # a slip log (CSV: t, Fx, Fz, load) under data/slip, as `ftfof import-logs --protocol slip`
    # writes it (null: the slip test simulated on the preset, a round trip)
    log: str | None = None


class LogColumns(Strict):
    time: str = "t"
    x: str = "x"
    z: str = "z"
    Fz: str = "Fz"
    Fx: str | None = "Fx"  # optional
    # optional: nonzero on the rows of the platform's proof pull after the landing hold, to the
    # log's end (docs/pipeline.md, "import-logs"); a log without it supplies no `holds` target
    proof: str | None = "proof"


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
