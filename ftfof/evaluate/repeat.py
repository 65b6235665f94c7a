"""The simulator's own repeatability: the bound on how well any surrogate can rank the front.

A robot places its foot to within its repeatability (``optimize.verify_repeatability``), so the
simulator's answer for a commanded trajectory is itself a draw. Evaluate simulates each member
the fidelity statistics measure twice more, each time with every free control value off by a
fresh normal draw of that size. The rank correlation between the two runs is the best a
predictor of the commanded trajectory can expect on that front: a fidelity goal above it
measures the simulator's noise, not the surrogate's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from ftfof.evaluate.fidelity import run_objectives
from ftfof.evaluate.runs import REPEAT
from ftfof.evaluate.simcheck import perturbed_runs
from ftfof.seeds import seed_for
from ftfof.sim.spec import Bench, SampleSpec
from ftfof.stats import rank_rho
from ftfof.trajectory.policy import ConstraintPolicy

REPEATS = (f"{REPEAT}1", f"{REPEAT}2")  # the two runs' sources; the sample id is the front row
HELD_PULL = "held_pull"  # the landed pad's pull, ranked beside the objectives


def repeat_specs(
    on: Bench,
    policy: ConstraintPolicy,
    members: Mapping[int, np.ndarray],
    error: float,
    seed: int,
) -> tuple[list[SampleSpec], dict[str, np.ndarray]]:
    """Two runs of each member (front row -> decision vector), every free control value off by
    a normal error of ``error`` (m), drawn per row from ``seed``'s ``repeat`` stream; with the
    decision vectors by key."""
    specs, controls = [], {}
    for row, X in members.items():
        rng = np.random.default_rng(seed_for(seed, "repeat", row))
        _, *copies = perturbed_runs(policy, X, error, len(REPEATS), rng)
        for source, copy in zip(REPEATS, copies, strict=True):
            spec = on.bezier(source, row, copy)
            specs.append(spec)
            controls[spec.key] = copy
    return specs, controls


def repeatability(
    names: Sequence[str],
    policy: ConstraintPolicy,
    runs: pd.DataFrame,
    time_base: np.ndarray,
    hold: float,
    pre_pressure: float,
) -> dict[str, dict[str, float | int | None]] | None:
    """Per objective and for the held pull: Spearman's rho between the two repeatability
    ``runs`` of each member, over the members both of whose runs succeeded (None: none did)."""
    ok = runs[runs.status == "ok"]
    if ok.empty:
        return None
    pair = [ok[ok.source == s].set_index("sample_id") for s in REPEATS]
    rows = sorted(set(pair[0].index) & set(pair[1].index))
    values = []
    for frame in (p.loc[rows] for p in pair):
        objectives = run_objectives(names, policy, frame, time_base, hold, pre_pressure)
        held = frame.get(HELD_PULL, pd.Series(np.nan, index=frame.index))
        values.append(np.column_stack([objectives, held.to_numpy(float)]))
    bound = {}
    for j, name in enumerate([*names, HELD_PULL]):
        rho = rank_rho(values[0][:, j], values[1][:, j])
        bound[name] = {"n": len(rows), "spearman": round(rho, 4) if np.isfinite(rho) else None}
    return bound
