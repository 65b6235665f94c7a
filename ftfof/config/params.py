"""The whole ``params.yaml``: the robots, surfaces and stage settings, checked together."""

from __future__ import annotations

from pydantic import (
    model_validator,
)

from ftfof.config.common import Strict
from ftfof.config.robot import (
    SHEAR_SAFETY_FACTOR,
    STANCE_FEET,
    Robot,
    Surface,
    min_shear_capacity_ratio,
)
from ftfof.config.stages import (
    Acquire,
    Base,
    Baselines,
    Climb,
    Dataset,
    Evaluate,
    Feasibility,
    Identify,
    Logs,
    Optimize,
    Platform,
    Polish,
    Refine,
    Sample,
    Study,
    Train,
)


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
    climb: Climb = Climb()
    study: Study = Study()
    identify: Identify = Identify()

    @model_validator(mode="after")
    def _selected_presets_exist(self) -> Params:
        # The message names its key: an error of the whole model has no location of its own.
        for key, name, presets in (
            ("robot", self.robot, self.robots),
            ("surface", self.surface, self.surfaces),
            ("identify.surface", self.identify.surface or self.surface, self.surfaces),
            *(
                [("climb.surface_change.surface", change.surface, self.surfaces)]
                if (change := self.climb.surface_change)
                else []
            ),
            ("evaluate.slip_scenario.surface", self.evaluate.slip_scenario.surface, self.surfaces),
        ):
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
    def _the_polish_has_a_spread_to_weigh(self) -> Params:
        # one run per trajectory has no standard deviation: risk_sigmas would silently do nothing
        if self.polish.risk_sigmas > 0 and self.optimize.verify_copies == 0:
            raise ValueError(
                f"polish.risk_sigmas: {self.polish.risk_sigmas:g} weighs the spread over each "
                "trajectory's runs, but optimize.verify_copies is 0 (one run each); set "
                "verify_copies to 1 or more, or risk_sigmas to 0"
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

    @model_validator(mode="after")
    def _the_proof_hold_fits_the_stance(self) -> Params:
        robot = self.selected_robot
        if robot.proof is None:
            return self
        stance = STANCE_FEET * robot.timing.T3
        hold = self.platform.protocol.proof_hold
        if hold > stance:
            raise ValueError(
                f"platform.protocol.proof_hold: {hold:g} s is longer than robot {self.robot!r}'s"
                f" stance, {stance:g} s (its other three feet's swings), the longest a landed"
                " pad is pulled before it lifts again"
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
