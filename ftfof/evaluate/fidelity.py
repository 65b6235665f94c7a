"""How well the surrogates' objectives predict the simulator's, over the re-simulated front.

The simulated channels become the surrogate's targets exactly as the dataset makes them
(:func:`ftfof.data.targets.binned`), so predicted and simulated objectives measure the same thing.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ftfof.data import targets
from ftfof.evaluate.runs import channels
from ftfof.objectives import Evidence, strategy_values
from ftfof.stats import rank_rho
from ftfof.trajectory.bezier import DECISION_NAMES
from ftfof.trajectory.policy import ConstraintPolicy

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Fidelity:
    objective: str
    n: int
    mean_abs_error: float
    median_relative_error: float  # |predicted - simulated| / |simulated|, simulated != 0
    spearman: float  # rank correlation; NaN with fewer than 3 points or a constant column

    def as_dict(self) -> dict:
        return {
            "n": self.n,
            "mean_abs_error": self.mean_abs_error,
            "median_relative_error": self.median_relative_error,
            "spearman": self.spearman,
        }


def simulated_objectives(
    names: Sequence[str],
    policy: ConstraintPolicy,
    X: Array,
    records: Sequence[Mapping[str, Array]],
    force_t: Array,
    hold: float,
    pre_pressure: float,
) -> Array:
    """(n, len(names)) objectives of the decision rows ``X`` from their simulated channels
    (an acquisition's full-rate series, time from the trajectory start)."""
    T3 = policy.timing.T3
    T2 = policy.timing.T2
    binned = [targets.binned(r, T3, hold, len(force_t), T2) for r in records]
    series = {k: np.stack([b[k] for b in binned]) for k in targets.TARGETS}
    path = policy.sample(np.atleast_2d(X))
    evidence = Evidence(
        series=series,
        dt=float(force_t[1] - force_t[0]),
        position=path.position,
        velocity=path.velocity,
        t=path.t,
        adhesion=(policy.timing.T2, T3),
        pre_pressure=pre_pressure,
        min_step=policy.feasibility.min_step,
    )
    return strategy_values(names, evidence)


def run_objectives(
    names: Sequence[str],
    policy: ConstraintPolicy,
    runs: pd.DataFrame,
    force_t: Array,
    hold: float,
    pre_pressure: float,
) -> Array:
    """:func:`simulated_objectives` of a table of re-simulations, from each run's decision
    columns and channels."""
    return simulated_objectives(
        names,
        policy,
        runs[list(DECISION_NAMES)].to_numpy(dtype=float),
        [channels(r) for _, r in runs.iterrows()],  # a few tens of runs, once per evaluation
        force_t,
        hold,
        pre_pressure,
    )


def fidelity(names: Sequence[str], predicted: Array, simulated: Array) -> list[Fidelity]:
    """Per objective: mean absolute error, median relative error and Spearman's rho."""
    predicted, simulated = np.atleast_2d(predicted), np.atleast_2d(simulated)
    if predicted.shape != simulated.shape or predicted.shape[1] != len(names):
        raise ValueError(
            f"predicted {predicted.shape} and simulated {simulated.shape} must both be "
            f"(n, {len(names)})"
        )
    out = []
    for j, name in enumerate(names):
        p, s = predicted[:, j], simulated[:, j]
        error = np.abs(p - s)
        nonzero = np.abs(s) > 1e-12
        relative = np.median(error[nonzero] / np.abs(s[nonzero])) if nonzero.any() else np.nan
        out.append(Fidelity(name, len(p), float(error.mean()), float(relative), rank_rho(p, s)))
    return out


def relative_error(predicted: float, simulated: float) -> float:
    """|predicted - simulated| / |simulated|; NaN when the simulated value is zero."""
    return abs(predicted - simulated) / abs(simulated) if abs(simulated) > 1e-12 else float("nan")


def target_met(
    fid: Fidelity, optimum_error: float, min_spearman: float, max_relative_error: float
) -> bool:
    """Whether one objective's fidelity over a set of points (and ``optimum_error``, the relative
    error at the chosen optimum) meets a target; NaN never meets it."""
    return bool(
        fid.spearman >= min_spearman
        and fid.median_relative_error <= max_relative_error
        and optimum_error <= max_relative_error
    )
