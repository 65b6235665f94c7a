"""The evaluation report's values and figures, from an :class:`~ftfof.evaluate.run.Evaluation`:
what the template shows, in the template's terms; and the page itself (:func:`evaluation_page`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from ftfof.evaluate.choice import TABLE_ANALOGUE, Candidate
from ftfof.evaluate.repeat import HELD_PULL
from ftfof.evaluate.run import Evaluation, Inputs
from ftfof.evaluate.runs import OPTIMUM, PAPER_OPTIMUM, compared, table_name
from ftfof.evaluate.step_check import CHECKED
from ftfof.evaluate.table import COLUMNS, MOVED, NOT_CLIMBED, PEAKS, TableRow
from ftfof.optimize.polish import POLISH
from ftfof.optimize.select import FRONT
from ftfof.report.climb import climb_rows
from ftfof.report.evaluation import (
    choice_figure,
    fidelity_figure,
    forces_figure,
    jitter_figure,
    paths_figure,
)
from ftfof.report.html import figure_data_uri, render
from ftfof.report.summary import GLOSSARY, run_this
from ftfof.report.summary import tables as summary_tables
from ftfof.robot import RobotContext

PARETO = (
    ("optimize_star.png", "Pareto front, star coordinates (cf. FTFOF Fig. 10)"),
    ("optimize_pcp.png", "Pareto front, parallel coordinates"),
    ("optimize_convergence.png", "NSGA-II convergence: normalised hypervolume, feasible count"),
)
TRAINING = (
    ("train_loss.png", "Training and validation loss per model (cf. FTFOF Fig. 8)"),
    ("train_predictions.png", "Validation predictions against simulation (cf. FTFOF Fig. 9)"),
)
REFINEMENT = (
    ("refine_fidelity.png", "Fidelity on each refinement round's points, before training on them"),
)
STAGE_FIGURES = (*PARETO, *TRAINING, *REFINEMENT)  # the PNGs the stages before evaluate write
PLOTTED = ("t", "x_cmd", "z_cmd", "Fd", "Fp", "body_acc")  # channels the report's figures use


def plotted_channels(df: pd.DataFrame, reference: str) -> dict[str, dict[str, np.ndarray]]:
    """By Table I name, the channels the report's figures draw, of each compared run in ``df``."""
    return {
        name: {c: np.asarray(row[c], dtype=float) for c in PLOTTED}
        for name, row in compared(df, reference).items()
    }


def simulation_figures(
    df: pd.DataFrame,
    predicted: np.ndarray,
    simulated: np.ndarray,
    objectives: list[str],
    reference: str,
    rows: list[TableRow],
    candidates: list[Candidate],
) -> dict[str, str]:
    """Fig. 11, 12, 14 from the simulated channels of the optimum and baselines; fidelity; the
    choice among the simulated candidates (when there were any), with the reference trajectory
    and the published optimum placed by their Table I values."""
    channels = plotted_channels(df, reference)
    figures = {
        "paths": figure_data_uri(paths_figure(channels, OPTIMUM)),
        "forces": figure_data_uri(forces_figure(channels, OPTIMUM)),
        "jitter": figure_data_uri(jitter_figure(channels, OPTIMUM)),
        "fidelity": figure_data_uri(fidelity_figure(objectives, predicted, simulated, 0)),
    }
    if candidates:
        figures["choice"] = figure_data_uri(_choice_figure(objectives, rows, reference, candidates))
    return figures


def _choice_figure(
    objectives: list[str], rows: list[TableRow], reference: str, candidates: list[Candidate]
):
    """The choice on the first two priorities; the reference trajectory and the published optimum
    placed where Table I measures those objectives on one nominal run, if it does."""
    axes = (objectives[0], objectives[1])
    columns = [TABLE_ANALOGUE.get(name) for name in axes]
    placed: dict[str, tuple[float, float]] = {}
    if None not in columns:
        table = {r.trajectory: r.values for r in rows}
        for name in (reference, table_name(PAPER_OPTIMUM)):
            if name in table:
                placed[name] = (table[name][columns[0]], table[name][columns[1]])
    return choice_figure(candidates, axes, placed)


def report_context(
    ev: Evaluation,
    ctx: RobotContext,
    inputs: Inputs,
    surface: str,
    reference: str,
    climb_steps: int = 0,
) -> dict[str, Any]:
    """The report template's values and the figures drawn from the simulations, but for the
    stages' own figures and the export path (``climb_steps``: the climbs' planned steps)."""
    return {
        "figures": simulation_figures(
            ev.table,
            ev.predicted,
            ev.simulated,
            inputs.objectives,
            reference,
            ev.rows,
            ev.candidates,
        ),
        **_run_context(ctx, surface, inputs, reference),
        **_choice_and_tables(ev, ctx, inputs, reference),
        **_climb_context(ev.summary, ev.rows, climb_steps, ctx),
        "fidelity": [
            {"objective": f.objective, **f.as_dict(), "bound": _bound(ev.summary, f.objective)}
            for f in ev.fidelity
        ],
        "hold_fidelity": ev.summary.get("hold_fidelity"),
        "held_pull_bound": _bound(ev.summary, HELD_PULL),
        "front_points": len(ev.predicted) - 1,
        "objectives": inputs.objectives,
        "optimum_predicted": ev.predicted[0].tolist(),
        "optimum_simulated": ev.simulated[0].tolist(),
        "pareto": PARETO,
        "training": TRAINING,
        "refinement": REFINEMENT,
        "export": _export_context(ev.summary["export"], ctx),
    }


def _run_context(ctx: RobotContext, surface: str, inputs: Inputs, reference: str) -> dict[str, Any]:
    """What was run: robot, surface, models and simulator, the optimum's row and the front's
    make-up; the Table I columns in display units."""
    import exudyn

    origin = inputs.front.origin
    return {
        "robot": ctx.name,
        "surface": surface,
        "models_digest": inputs.optimum["models_digest"],
        "exudyn": exudyn.__version__,
        "optimum_row": inputs.optimum["front_row"],
        "optimum_origin": inputs.optimum["origin"],
        "front_size": int((origin == FRONT).sum()),
        "nominees": int(((origin != FRONT) & (origin != POLISH)).sum()),
        "polished": int((origin == POLISH).sum()),
        "reference": reference,
        "columns": [
            {
                "key": c,
                "label": label,
                **({"unit": "mm", "scale": 1e3} if unit == "m" else {"unit": unit, "scale": 1.0}),
            }
            for c, label, unit in COLUMNS
        ],
    }


def _choice_and_tables(
    ev: Evaluation, ctx: RobotContext, inputs: Inputs, reference: str
) -> dict[str, Any]:
    """The front's simulations, the choice, the tables against the reference and the published
    optimum, the step and film checks."""
    summary, rows = ev.summary, ev.rows
    return {
        "front_simulated": summary["front_simulated"],
        "choice": _choice_context(
            inputs.optimum["rhs"], ev.candidates, inputs.objectives[0], summary["choice"]
        ),
        "paper_columns": [{"key": c, "label": label} for c, label, _ in PEAKS],
        # the paper's Table I describes the robot whose optimum it published
        "paper_robot": ctx.robot.published_optimum is not None,
        "tables": summary_tables(
            rows, reference, ctx.robot.pre_pressure, summary["robot_rules_broken"]
        ),
        "reference_reason": summary["reference_reason"],
        "run_this": run_this(
            rows,
            reference,
            ctx.robot.pre_pressure,
            inputs.optimum["decision"],
            inputs.optimum["rhs"],
            summary["choice"].get("candidates", 0),
        ),
        "glossary": GLOSSARY,
        "pre_pressure": ctx.robot.pre_pressure,
        "step_check": summary["step_check"],
        "film_check": summary["film_check"],
        "step_columns": [{"key": c, "label": label, "unit": unit} for c, label, unit in CHECKED],
        "step_labels": {c: label for c, label, _ in CHECKED},
        "table": [
            {"trajectory": r.trajectory, "values": r.values, "change": r.change} for r in rows
        ],
        "paper": summary["paper_optimal_change_vs_polynomial"],
    }


def _climb_context(
    summary: Mapping[str, Any], rows: list[TableRow], climb_steps: int, ctx: RobotContext
) -> dict[str, Any]:
    """The climbs' rows (of ``climb_steps`` planned steps) and the trajectories not climbed."""
    return {
        "climb": climb_rows(
            summary.get("climb", {}),
            rows,
            climb_steps,
            ctx.robot.published_optimum is not None,
        ),
        "climb_skipped": summary.get("climb", {}).get(NOT_CLIMBED, {}),
        "climb_moved": summary.get("climb", {}).get(MOVED),
        "climb_steps": climb_steps,
    }


def _bound(summary: Mapping[str, Any], name: str) -> float | None:
    """The simulator's own rank correlation for ``name`` (None: not measured)."""
    bound = summary.get("fidelity_bound") or {}
    return bound.get(name, {}).get("spearman")


def _export_context(export: Mapping[str, Any], ctx: RobotContext) -> dict[str, Any]:
    """The controller export in the template's terms: rows, rate, duration, leg and limits."""
    return {
        "rows": export["rows"],
        "rate": export["rate_hz"],
        "duration": float(ctx.policy.timing.T3),
        "leg": ctx.robot.leg.type,
        "within_limits": export["within_joint_limits"],
        "peak_speed": ", ".join(f"{v:.2f}" for v in export["peak_joint_speed"]),
    }


def evaluation_page(
    ev: Evaluation,
    ctx: RobotContext,
    inputs: Inputs,
    surface: str,
    climb_steps: int,
    stage_figures: Mapping[str, str],
    robot_figures: Mapping[str, str],
    export_path: str,
    rounds: list[dict],
    slip_scenario: Mapping[str, Any],
) -> str:
    """The self-contained HTML report: :func:`report_context` with the earlier stages' and the
    robot's stages' figures (data URIs: the climb, the slip comparison, the ε study), the
    export's path, refine's ``rounds`` and the slip comparison's scenario (its table is the
    summary's ``slip``, where it ran)."""
    values = report_context(ev, ctx, inputs, surface, ev.summary["reference"], climb_steps)
    values["eps_study"] = ev.summary["eps_study"]
    slip = ev.summary.get("slip")
    values["slip"] = {**slip_scenario, "table": slip} if slip else None
    values["figures"] = {
        **stage_figures,
        **values["figures"],
        **robot_figures,
    }
    return render({**values, "export_path": export_path, "refine": rounds})


def _choice_context(
    rhs: dict[str, Any], candidates: list[Candidate], first: str, summary: dict[str, Any]
) -> dict[str, Any]:
    """The choice's table (sorted by the ``first`` priority), its ``summary`` (the metrics) and
    RHS's visits, for the template."""
    return {
        "summary": summary,
        "candidates": sorted(candidates, key=lambda c: (c.mean[first], c.row)),
        "alpha": rhs["alpha"],
        "beta": rhs["beta"],
        "resolution": rhs["resolution"],
        "steps": [{**s, "kept": len(s["remaining"])} for s in rhs["steps"]],
        "tie_break": rhs["tie_break"],
    }
