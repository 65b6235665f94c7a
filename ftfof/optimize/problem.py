"""The trajectory search posed to pymoo: free control-point coordinates -> objectives, constraints.

One call evaluates a whole population: the trajectories are sampled twice (on the surrogate's
time base and on the policy's check grid), the multi-output surrogate runs once over the
population, and the strategy functions and constraint rules are vectorised over it. Nothing loops
per individual.

Decision variables are the policy's free variables (ties reparameterised away) with its box;
objectives are the robot's priority list; the inequality constraints are the policy's rules that
the box does not already enforce (relational, shape, sampled position/velocity limits, fs6,
md_path, the minimum path radius and the no-cusp rule), divided by a unit scale per kind so that
pymoo's summed violation compares like with like, and the foot's physical limits on what the
surrogate predicts (:data:`PHYSICAL`, dimensionless), each where the surrogate was
trained on its channel.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache

import numpy as np
from numpy.typing import NDArray
from pymoo.core.problem import Problem
from threadpoolctl import ThreadpoolController

from ftfof.data.release import swing_gap
from ftfof.objectives import (
    Evidence,
    film_safety,
    fs3_pre_pressure_error,
    pad_clearance,
    pad_holds,
    pad_retouch,
    strategy_values,
)
from ftfof.rules import FootRules
from ftfof.surrogate.predict import Surrogate
from ftfof.trajectory.policy import Constraint, ConstraintPolicy, FeasibilityReport

Array = NDArray[np.float64]


# What a real foot must survive, measured in the simulator and predicted by the surrogate, each on
# the channel it needs. g <= 0 where it holds. ``film_safety``: fc * max film curvature - 1.
# ``pad_clearance``, the clean release of :mod:`ftfof.data.release` on the predicted clearance: the
# larger of 1 - max clearance / swing_clearance (the whole pad rises clear) and 1 - swing gap /
# detached (once risen, it stays at least the switch's height off the wall until the landing).
# ``pad_retouch``: the same release's last part, on the predicted bonds re-formed between complete
# detachment and the landing segment (:func:`ftfof.objectives.pad_retouch`), where the robot allows
# a number. ``landing_press``, :mod:`ftfof.data.landing` on the predicted landing pre-pressure:
# fs3 / (tolerance x a) - 1, where the robot has a landing tolerance. ``pad_holds``, the proof
# pull's rule (:func:`ftfof.data.faults.hold_fault`) on the predicted verdict: 1 - max / 0.5, more
# likely than not the landed pad holds F_proof, where the robot's rules ask for it.
PHYSICAL: dict[str, str] = {
    "film_safety": "curvature",
    "pad_clearance": "clearance",
    "pad_retouch": "retouch",
    "landing_press": "Fp",
    "pad_holds": "holds",
}


def asked_limits(rules: FootRules) -> tuple[str, ...]:
    """The physical limits the robot asks for: the landing press and the retouch where it sets
    them."""
    optional = {
        "landing_press": rules.landing_tolerance,
        "pad_retouch": rules.retouch_allowed,
        "pad_holds": rules.proof_pull,
    }
    return tuple(name for name in PHYSICAL if optional.get(name, True) is not None)


def predicted_violations(
    rules: FootRules, series: Mapping[str, Array], t: Array, names: Sequence[str]
) -> dict[str, Array]:
    """name -> (pop,) g for the ``names`` limits, from predicted series on the times ``t``."""

    def release() -> Array:
        clearance = series["clearance"]
        gap = swing_gap(clearance, t, rules.swing_clearance, rules.landing_start)
        return np.maximum(
            pad_clearance(clearance, rules.swing_clearance), 1.0 - gap / rules.detached
        )

    def landing() -> Array:
        assert rules.landing_tolerance is not None  # asked_limits() asks for it only then
        allowed = rules.landing_tolerance * rules.pre_pressure
        return fs3_pre_pressure_error(series["Fp"], rules.pre_pressure) / allowed - 1.0

    measures = {
        "film_safety": lambda: film_safety(series["curvature"], rules.film.radius),
        "pad_clearance": release,
        "pad_retouch": lambda: pad_retouch(series["retouch"], rules.retouch_allowed),
        "landing_press": landing,
        "pad_holds": lambda: pad_holds(series["holds"]),
    }
    return {name: measures[name]() for name in names}


@dataclass(frozen=True)
class PopulationEvaluation:
    """Everything one evaluation produced: objectives, raw rule violations and predicted forces."""

    X: Array  # (pop, 12) full decision vectors
    F: Array  # (pop, n_obj) in priority order
    violations: FeasibilityReport  # the non-box rules, in their units (> 0 violated)
    series: dict[str, Array]  # target -> (pop, seq_len) predicted series, in its unit
    physical: dict[str, Array]  # PHYSICAL name -> (pop,) predicted g (> 0 violated)
    t: Array  # the surrogate's time base


class TrajectoryProblem(Problem):
    """Minimise the robot's strategy functions on the surrogates' predictions."""

    def __init__(
        self,
        policy: ConstraintPolicy,
        surrogate: Surrogate,
        objectives: Sequence[str],
        rules: FootRules,
    ):
        self.policy = policy
        self.surrogate = surrogate
        self.objectives = tuple(objectives)
        self.pre_pressure = rules.pre_pressure
        self.foot_rules = rules
        # the limits asked for whose channel the surrogate was trained on
        self.physical = tuple(n for n in asked_limits(rules) if PHYSICAL[n] in surrogate.trained)
        # asked for, but the surrogate has not the channel: the search cannot see them
        self.unconstrained = tuple(n for n in asked_limits(rules) if n not in self.physical)
        self.rules: tuple[Constraint, ...] = tuple(c for c in policy.constraints if not c.box)
        self.scales = np.array([_unit_scale(c.kind, policy) for c in self.rules])
        self.force_t = surrogate.time_base(policy.timing.T3)
        super().__init__(
            n_var=policy.n_free,
            n_obj=len(self.objectives),
            n_ieq_constr=len(self.rules) + len(self.physical),
            xl=policy.lower,
            xu=policy.upper,
        )

    def evaluate_population(self, free: Array) -> PopulationEvaluation:
        """Objectives, violations and predicted forces for free-variable rows (pop, n_free)."""
        # The BLAS calls here are tiny; OpenBLAS threads spinning after each one would steal the
        # cores the compiled surrogate runs on (measured: one evaluation 38 ms -> 21 ms).
        with _blas_controller().limit(limits=1, user_api="blas"):
            return self._evaluate_population(free)

    def _evaluate_population(self, free: Array) -> PopulationEvaluation:
        X = self.policy.expand(free)
        path = self.policy.sample(X)
        on_base = self.policy.sample(X, self.force_t)
        series = self.surrogate.predict(on_base.position, on_base.velocity, decisions=X)
        timing = self.policy.timing
        evidence = Evidence(
            series=series,
            dt=float(self.force_t[1] - self.force_t[0]),
            position=path.position,
            velocity=path.velocity,
            t=path.t,
            adhesion=(timing.T2, timing.T3),
            pre_pressure=self.pre_pressure,
            min_step=self.policy.feasibility.min_step,
        )
        F = strategy_values(self.objectives, evidence)
        report = self.policy.check(X, samples=path, constraints=self.rules)
        physical = predicted_violations(self.foot_rules, series, self.force_t, self.physical)
        return PopulationEvaluation(X, F, report, series, physical, self.force_t)

    def _evaluate(self, x: Array, out: dict, *args, **kwargs) -> None:
        result = self.evaluate_population(x)
        out["F"] = result.F
        G = result.violations.violations / self.scales
        out["G"] = np.column_stack([G, *result.physical.values()])


@cache
def _blas_controller() -> ThreadpoolController:
    return ThreadpoolController()


def _unit_scale(kind: str, policy: ConstraintPolicy) -> float:
    """Metres by the position-limit size, m/s by the velocity-limit size, radians as they are."""
    if kind == "velocity_limit":
        return float(max(policy.limits.velocity))
    if kind == "bending":
        return 1.0
    return float(max(policy.limits.position))
