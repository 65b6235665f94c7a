"""The evaluation of an optimum from its re-simulations: front sampling, the Table I analogue,
surrogate fidelity, the controller export, the metrics and the report's values.

Every number here comes from the simulations, never from the surrogates, whose predictions are
only compared with them (surrogate fidelity).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from ftfof.config import Evaluate as EvaluateSettings
from ftfof.config import Solver
from ftfof.errors import DataError, SimulationError
from ftfof.evaluate.choice import Candidate, choice_summary, rhs_candidates
from ftfof.evaluate.export import ControllerTrajectory, ExportRateError, controller_trajectory
from ftfof.evaluate.feasible import reference_for
from ftfof.evaluate.fidelity import Fidelity, fidelity, run_objectives
from ftfof.evaluate.film_check import FilmCheck
from ftfof.evaluate.members import judged_front, rounded
from ftfof.evaluate.repeat import repeatability
from ftfof.evaluate.runs import (
    OPTIMUM,
    PAPER_OPTIMUM,
    channels,
    compared,
    ok_rows,
    run_name,
    simulated_rows,
    split_runs,
    table_name,
    table_rows,
)
from ftfof.evaluate.step_check import StepCheck, checked_figures, step_check
from ftfof.evaluate.table import PAPER_TABLE_I, PEAKS, TableRow, table_one
from ftfof.kinematics.legs import build_leg
from ftfof.optimize.select import FRONT
from ftfof.robot import RobotContext
from ftfof.stats import rank_rho
from ftfof.surrogate.predict import Surrogate
from ftfof.trajectory.baselines import BezierTrajectory
from ftfof.trajectory.bezier import DECISION_NAMES


@dataclass
class Inputs:
    """What `optimize` left: the chosen row and the front it came from, checked against params."""

    optimum: dict[str, Any]
    front: pd.DataFrame  # indexed by front row
    objectives: list[str]
    digest: str


def front_sample(inputs: Inputs, k: int) -> list[int]:
    """``k`` front rows spread evenly along the priority-sorted front, the optimum and the
    nominees (simulated before, not members of this front) left out."""
    front = inputs.front
    if "origin" not in front:
        raise DataError("front.parquet", "has no origin column (re-run `ftfof optimize`)")
    member = front.recheck_feasible & (front.origin == FRONT)
    rows = front.index[member & (front.index != inputs.optimum["front_row"])]
    rows = rows.to_numpy()
    if k == 0 or rows.size == 0:
        return []
    picks = np.unique(np.round(np.linspace(0, rows.size - 1, min(k, rows.size))).astype(int))
    return [int(r) for r in rows[picks]]


def fidelity_members(inputs: Inputs, front_rows: list[int]) -> dict[int, np.ndarray]:
    """The decision vectors by front row of the runs the fidelity statistics measure: the
    sampled ``front_rows``, and the optimum where it is a member of the front."""
    rows = [inputs.optimum["front_row"]] if from_front(inputs) else []
    return {row: decision(inputs, row) for row in [*rows, *front_rows]}


def decision(inputs: Inputs, row: int) -> np.ndarray:
    """The decision variables (m) of one front row."""
    return inputs.front.loc[row, list(DECISION_NAMES)].to_numpy(dtype=float)


def bezier_rows(ctx: RobotContext, inputs: Inputs) -> dict[str, np.ndarray]:
    """Table I's Bezier rows by name: the chosen optimum, and the robot's published one where it
    has one (the rows judged on every rule, :func:`ftfof.evaluate.feasible.admitted`)."""
    rows = {"optimum": decision(inputs, inputs.optimum["front_row"])}
    if ctx.robot.published_optimum is not None:
        rows[table_name(PAPER_OPTIMUM)] = np.asarray(ctx.robot.published_optimum)
    return rows


def checked_on_both_films(
    check: int | None, nodes: int, ctx: RobotContext, table: pd.DataFrame, film: pd.DataFrame
) -> FilmCheck | None:
    """Every successful run's min bend radius at the acquisition's ``nodes`` (``table``) and on
    ``check`` elements (``film``); None without a check film."""
    if check is None:
        return None

    def radii(df: pd.DataFrame) -> dict[str, float]:
        """Successful runs that peeled (no free span: an infinite radius, nothing to compare)."""
        ok = df[(df.status == "ok") & np.isfinite(df.min_bend_radius.astype(float))]
        return {
            run_name(r.source, int(r.sample_id)): float(r.min_bend_radius) for r in ok.itertuples()
        }

    fc = ctx.robot.foot.film_min_bend_radius
    return FilmCheck(nodes, check, fc, radii(table), radii(film))


def checked_at_both_steps(
    cfg: EvaluateSettings,
    reference: str,
    step: float,
    table: pd.DataFrame,
    fine: pd.DataFrame,
    T3: float,
) -> StepCheck | None:
    """Table I's trajectories at the acquisition's ``step`` (``table``, its successful runs) and
    at ``evaluate.check_step`` (``fine``); a run that failed at the check step is left out and
    named. None without a check step."""
    if cfg.check_step is None:
        return None
    at_step = {
        name: checked_figures(channels(row), row, T3)
        for name, row in compared(table, reference).items()
    }
    at_check = {
        table_name(row.source): checked_figures(channels(row), row, T3)
        for _, row in fine[fine.status == "ok"].iterrows()
    }
    return step_check(at_step, at_check, reference, step, cfg.check_step)


def fidelity_of(
    inputs: Inputs, df: pd.DataFrame, ctx: RobotContext, surrogate: Surrogate
) -> tuple[list[Fidelity], np.ndarray, np.ndarray]:
    """Predicted (as the optimiser saw them) and simulated objectives; the optimum is row 0.
    A nominee optimum (simulated in an earlier refine round, so among the surrogates' training
    rows) is left out of the fidelity statistics, which then measure the front members alone."""
    names = inputs.objectives
    sims = simulated_rows(df)
    predicted = inputs.front.loc[sims.sample_id, names].to_numpy(dtype=float)
    simulated = run_objectives(
        names,
        ctx.policy,
        sims,
        surrogate.time_base(ctx.policy.timing.T3),
        surrogate.hold,
        ctx.robot.pre_pressure,
    )
    measured = slice(0 if from_front(inputs) else 1, None)
    return fidelity(names, predicted[measured], simulated[measured]), predicted, simulated


def hold_fidelity(inputs: Inputs, df: pd.DataFrame) -> dict[str, Any] | None:
    """How the search's predicted chance that a landed pad holds F_proof (its ``pad_holds``
    constraint, 1 - 2 chance) ranks the simulated members' held pull, and how often the chance's
    side of 0.5 is the simulated verdict; None where the search did not predict it."""
    column = "g:pad_holds"
    if column not in inputs.front.columns:
        return None
    sims = simulated_rows(df)
    measured = slice(0 if from_front(inputs) else 1, None)
    chance = (1.0 - inputs.front.loc[sims.sample_id, column].to_numpy(float)[measured]) / 2
    held_pull = sims.held_pull.to_numpy(float)[measured]
    held = sims.proof_held.to_numpy(float)[measured] == 1.0
    return {
        "n": int(chance.size),
        "spearman_held_pull": rounded(rank_rho(chance, held_pull)),
        "verdict_agreement": rounded(float(np.mean((chance >= 0.5) == held))),
    }


def from_front(inputs: Inputs) -> bool:
    """Whether the optimum is a member of its front (not a nominee of earlier simulations)."""
    return inputs.optimum["origin"] == FRONT


def export(ctx: RobotContext, X: np.ndarray, rate: float) -> ControllerTrajectory:
    """The decision row ``X`` as joint commands at ``rate`` Hz for the robot's controller."""
    try:
        trajectory = BezierTrajectory(ctx.policy, X)
        return controller_trajectory(
            trajectory, ctx.policy.timing.T3, build_leg(ctx.robot.leg), rate
        )
    except ExportRateError as err:
        raise SimulationError("evaluate.export_rate_hz", str(err)) from None
    except ValueError as err:  # the optimum leaves the leg's reach
        raise SimulationError("optimum export", str(err)) from None


def metrics(
    cfg: EvaluateSettings,
    robot: str,
    surface: str,
    inputs: Inputs,
    rows: list[TableRow],
    fid: list[Fidelity],
    controller: ControllerTrajectory,
    n_fidelity: int,
    front: dict[str, Any],
) -> dict[str, Any]:
    """The stage's metrics: Table I changes, the paper's, fidelity, the choice and the export."""

    def entry(row) -> dict:
        out = {}
        for c in row.values:
            out[c] = round(row.values[c], 4)
            if np.isfinite(row.change[c]):  # JSON has no NaN: no change from a reference of 0
                out[f"{c}_change"] = round(row.change[c], 2)
        return out

    paper = {r.trajectory: r for r in table_one(PAPER_TABLE_I, "polynomial")}["optimal"]
    return {
        "robot": robot,
        "surface": surface,
        "reference": cfg.reference,
        "table": {r.trajectory: entry(r) for r in rows},
        "paper_optimal_change_vs_polynomial": {c: round(paper.change[c], 2) for c, _, _ in PEAKS},
        "fidelity": {f.objective: f.as_dict() for f in fid},
        "fidelity_points": n_fidelity,
        "front_simulated": front,
        "optimum_front_row": inputs.optimum["front_row"],
        "optimum_origin": inputs.optimum[
            "origin"
        ],  # front, or the refine round it was simulated in
        "export": {
            "rows": int(controller.table.shape[0]),
            "rate_hz": cfg.export_rate_hz,
            "within_joint_limits": controller.within_joint_limits,
            "peak_joint_speed": [round(float(v), 4) for v in controller.peak_joint_speed],
        },
    }


@dataclass
class Evaluation:
    """What the re-simulations say: the metrics and the parts the report draws."""

    summary: dict[str, Any]  # the stage's metrics
    table: pd.DataFrame  # the successful runs at the acquisition's settings
    rows: list[TableRow]  # the Table I analogue
    fidelity: list[Fidelity]
    predicted: np.ndarray  # (runs, objectives) as the optimiser saw them; the optimum is row 0
    simulated: np.ndarray  # the same from the simulated forces
    candidates: list[Candidate]  # the simulator-checked candidates RHS chose among
    controller: ControllerTrajectory  # the optimum for the robot's controller


def evaluate(
    cfg: EvaluateSettings,
    solver: Solver,
    surface: str,
    ctx: RobotContext,
    inputs: Inputs,
    simulations: pd.DataFrame,
    surrogate: Surrogate,
    breaks: Mapping[str, list[str]],
    exported: int | None = None,
) -> Evaluation:
    """Everything the report shows, from the re-simulations of the optimum, front and baselines
    (run with the acquisition's ``solver`` on ``surface``); ``breaks`` names the robot's rules
    each Table I trajectory breaks, and the changes are taken against one the robot can run.
    The export is the optimum, or the front row ``exported`` the choice moved to where the
    optimum fell on the robot (:func:`ftfof.pipeline.climb.moved_choice`)."""
    at_step, fine, on_film, repeats = split_runs(simulations)
    ok = at_step[at_step.status == "ok"]
    detachment = {
        table_name(s): float(ok[ok.source == s].iloc[0].peak_detachment)
        for s in ok.source
        if s.startswith("baseline:") and s != PAPER_OPTIMUM
    }
    reference, reason = reference_for(cfg.reference, ctx.robot.reference, breaks, detachment)
    table = ok_rows(at_step, reference)
    T3 = ctx.policy.timing.T3
    rows = table_rows(table, reference, T3)
    steps = checked_at_both_steps(cfg, reference, solver.step, table, fine, T3)
    films = checked_on_both_films(cfg.check_nodes, solver.nodes, ctx, table, on_film)
    front = judged_front(ctx, table, films)
    fid, predicted, simulated = fidelity_of(inputs, table, ctx, surrogate)
    chosen = inputs.optimum["front_row"] if exported is None else exported
    controller = export(ctx, decision(inputs, chosen), cfg.export_rate_hz)
    n_fidelity = len(predicted) - (0 if from_front(inputs) else 1)
    candidates = rhs_candidates(inputs.optimum, inputs.objectives)
    summary = metrics(cfg, ctx.name, surface, inputs, rows, fid, controller, n_fidelity, front)
    summary["reference"], summary["reference_reason"] = reference, reason
    summary["hold_fidelity"] = hold_fidelity(inputs, table)
    summary["fidelity_bound"] = repeatability(
        inputs.objectives,
        ctx.policy,
        repeats,
        surrogate.time_base(T3),
        surrogate.hold,
        ctx.robot.pre_pressure,
    )
    summary["robot_rules_broken"] = {name: list(rules) for name, rules in breaks.items()}
    summary["choice"] = choice_summary(candidates)
    summary["step_check"] = None if steps is None else steps.as_dict(OPTIMUM)
    summary["film_check"] = None if films is None else films.as_dict()
    return Evaluation(summary, table, rows, fid, predicted, simulated, candidates, controller)
