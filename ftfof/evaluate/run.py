"""The evaluation of an optimum from its re-simulations: front sampling, the Table I analogue,
surrogate fidelity, the controller export, the metrics and the report's values.

Every number here comes from the simulations, never from the surrogates, whose predictions are
only compared with them (surrogate fidelity).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from ftfof.config import Params
from ftfof.data import targets
from ftfof.data.dataset import CHANNELS
from ftfof.data.faults import foot_faults
from ftfof.errors import DataError, SimulationError
from ftfof.evaluate.choice import TABLE_ANALOGUE, Candidate, choice_summary, rhs_candidates
from ftfof.evaluate.export import ControllerTrajectory, ExportRateError, controller_trajectory
from ftfof.evaluate.fidelity import Fidelity, fidelity, simulated_objectives
from ftfof.evaluate.film_check import FILM, FilmCheck
from ftfof.evaluate.step_check import CHECKED, FINE, StepCheck, checked_figures, step_check
from ftfof.evaluate.table import COLUMNS, PAPER_TABLE_I, PEAKS, TableRow, table_one
from ftfof.kinematics.legs import build_leg
from ftfof.optimize.polish import POLISH
from ftfof.optimize.select import FRONT
from ftfof.robot import RobotContext
from ftfof.rules import FootRules
from ftfof.surrogate.predict import Surrogate
from ftfof.trajectory.baselines import BASELINE_NAMES
from ftfof.trajectory.bezier import DECISION_NAMES

OPTIMUM = "optimum"
PAPER_OPTIMUM = "baseline:paper_optimum"  # the published optimum, simulated, never fitted
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
PLOTTED = ("t", "x_cmd", "z_cmd", "Fd", "Fp", "body_acc")  # channels the report's figures use


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


def decision(inputs: Inputs, row: int) -> np.ndarray:
    """The decision variables (m) of one front row."""
    return inputs.front.loc[row, list(DECISION_NAMES)].to_numpy(dtype=float)


def ok_rows(df: pd.DataFrame, reference: str) -> pd.DataFrame:
    """The simulations that succeeded; a clear error when the optimum or the reference failed."""
    for source in (OPTIMUM, f"baseline:{reference}"):
        row = df[df.source == source]
        if row.empty or row.iloc[0].status != "ok":
            error = row.iloc[0].error if not row.empty else "missing"
            raise SimulationError(source, f"re-simulation failed: {error}")
    return df[df.status == "ok"]


def split_runs(simulations: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """The runs as the acquisition makes them, those at the check step and those on the check
    film (each with its ``FINE`` / ``FILM`` prefix removed from the source)."""
    fine = simulations.source.str.startswith(FINE)
    film = simulations.source.str.startswith(FILM)
    check, on_film = simulations[fine], simulations[film]
    return (
        simulations[~fine & ~film],
        check.assign(source=check.source.str.removeprefix(FINE)),
        on_film.assign(source=on_film.source.str.removeprefix(FILM)),
    )


def run_name(source: str, sample_id: int) -> str:
    """A run's name across checks: Table I's name, or ``front <row>`` for a front member."""
    return f"front {sample_id}" if source == "front" else table_name(source)


def checked_on_both_films(
    params: Params, ctx: RobotContext, table: pd.DataFrame, film: pd.DataFrame
) -> FilmCheck | None:
    """Every successful run's min bend radius at the acquisition's node count (``table``) and on
    ``evaluate.check_nodes`` elements (``film``); None without a check film."""
    check = params.evaluate.check_nodes
    if check is None:
        return None

    def radii(df: pd.DataFrame) -> dict[str, float]:
        """Successful runs that peeled (no free span: an infinite radius, nothing to compare)."""
        ok = df[(df.status == "ok") & np.isfinite(df.min_bend_radius.astype(float))]
        return {
            run_name(r.source, int(r.sample_id)): float(r.min_bend_radius) for r in ok.itertuples()
        }

    fc = ctx.robot.foot.film_min_bend_radius
    return FilmCheck(params.acquire.solver.nodes, check, fc, radii(table), radii(film))


def compared(df: pd.DataFrame, reference: str) -> dict[str, pd.Series]:
    """By display name, the rows of the table and the figures: the reference, the other
    baselines, the paper's published optimum (where the robot has one), then our optimum."""
    present = set(df.source)
    baselines = [f"baseline:{n}" for n in BASELINE_NAMES if f"baseline:{n}" in present]
    first = f"baseline:{reference}"
    sources = [first, *(s for s in baselines if s != first)]
    sources += [s for s in df.source if s == PAPER_OPTIMUM] + [OPTIMUM]
    return {table_name(s): df[df.source == s].iloc[0] for s in sources}


def table_name(source: str) -> str:
    """A simulation's name in Table I: its source without the ``baseline:`` prefix."""
    return source.removeprefix("baseline:")


def figures_of(row: pd.Series, T3: float) -> dict[str, float]:
    """One simulation's Table I figures: the acquisition's scalars and the detachment jitter."""
    out = {c: float(row[c]) for c, _, _ in COLUMNS if c != "jitter"}
    out["jitter"] = float(np.max(targets.full_rate(channels(row), T3)["body_acc"]))
    return out


def table_rows(df: pd.DataFrame, reference: str, T3: float) -> list[TableRow]:
    """The Table I analogue, with the foot's pull and film figures, against ``reference``."""
    peaks = {name: figures_of(row, T3) for name, row in compared(df, reference).items()}
    return table_one(peaks, reference, COLUMNS)


def checked_at_both_steps(
    params: Params, table: pd.DataFrame, fine: pd.DataFrame, T3: float
) -> StepCheck | None:
    """Table I's trajectories at the acquisition's step (``table``, its successful runs) and at
    ``evaluate.check_step`` (``fine``); a run that failed at the check step is left out and
    named. None without a check step."""
    cfg = params.evaluate
    if cfg.check_step is None:
        return None
    at_step = {
        name: checked_figures(channels(row), row, T3)
        for name, row in compared(table, cfg.reference).items()
    }
    at_check = {
        table_name(row.source): checked_figures(channels(row), row, T3)
        for _, row in fine[fine.status == "ok"].iterrows()
    }
    return step_check(at_step, at_check, cfg.reference, params.acquire.solver.step, cfg.check_step)


def front_members(
    df: pd.DataFrame, T3: float, rules: FootRules, films: FilmCheck | None = None
) -> dict:
    """The re-simulated optimum and front members side by side: what each trades (pull, jitter,
    landing press), whether its film survives, its pad lets go and clears the wall, it lands
    pressing within the robot's tolerance of a and the body shakes within the robot's limit
    (``rules``, the simulator check's, with where the film limit comes from), so the
    choice can be judged in simulation. With ``films``, each member's bend on the check film
    too, and whether it keeps fc there."""
    sims = simulated_rows(df)
    members = []
    for _, row in sims.iterrows():  # a few tens of rows, once per evaluation
        f = figures_of(row, T3)
        faults = foot_faults(
            np.asarray(row.t, dtype=float),
            np.asarray(row.bonds, dtype=float),
            np.asarray(row.Fp, dtype=float),
            {**f, "switch_time": float(row.switch_time), "max_clearance": float(row.max_clearance)},
            rules,
        )
        members.append(
            {
                "row": int(row.sample_id),
                "optimum": row.source == OPTIMUM,
                "peak_pull": round(f["peak_pull"], 4),
                "jitter": round(f["jitter"], 4),
                "landing_pre_pressure_error": round(
                    abs(f["landing_pre_pressure"] - rules.pre_pressure), 4
                ),
                "min_bend_radius": round(f["min_bend_radius"], 6),
                "film_safe": not faults.film,
                **_on_check_film(films, run_name(row.source, int(row.sample_id)), rules.film.fc),
                "max_clearance": round(float(row.max_clearance), 6),
                "lets_go": not faults.release,
                "release_fault": faults.release,
                "lands": not faults.landing,
                "landing_fault": faults.landing,
                "calm": not faults.shake,
                "shake_fault": faults.shake,
                "clean": faults.clean,  # a real foot could run it
            }
        )

    def fraction(key: str) -> float | None:
        """Over every member; one without a verdict (no run on the check film) counts as not
        verified."""
        return round(float(np.mean([bool(m[key]) for m in members])), 4) if members else None

    return {
        "members": members,
        "film_safe_fraction": fraction("film_safe"),
        "film_safe_on_check_film_fraction": fraction("film_safe_on_check_film")
        if films is not None
        else None,
        "lets_go_fraction": fraction("lets_go"),
        "lands_fraction": fraction("lands"),
        "calm_fraction": fraction("calm"),
        "clean_fraction": fraction("clean"),
        "film_limit": rules.film.as_dict(),
        "swing_clearance": rules.swing_clearance,
        "landing_tolerance": rules.landing_tolerance,
        "body_acc_limit": rules.body_acc_limit,
    }


def _on_check_film(films: FilmCheck | None, name: str, fc: float) -> dict[str, Any]:
    """A member's bend on the check film and whether it keeps fc there (None: no such run)."""
    if films is None:
        return {}
    pair = films.pair(name)
    return {
        "min_bend_radius_on_check_film": None if pair is None else round(pair[1], 6),
        "film_safe_on_check_film": None if pair is None else pair[1] >= fc,
    }


def judged_front(ctx: RobotContext, df: pd.DataFrame, films: FilmCheck | None = None) -> dict:
    """:func:`front_members` with the robot's rules."""
    return front_members(df, ctx.policy.timing.T3, ctx.rules, films)


def simulated_rows(df: pd.DataFrame) -> pd.DataFrame:
    """The re-simulated optimum, then the front members by row: the order of every per-member
    result (:func:`front_members`, :func:`fidelity_of`)."""
    sims = df[df.source.isin([OPTIMUM, "front"])]
    return sims.assign(first=sims.source != OPTIMUM).sort_values(["first", "sample_id"])


def channels(row: pd.Series) -> dict[str, np.ndarray]:
    """The full-rate channels the surrogate's targets are made of, as float arrays."""
    return {c: np.asarray(row[c], dtype=float) for c in CHANNELS}


def fidelity_of(
    inputs: Inputs, df: pd.DataFrame, ctx: RobotContext, surrogate: Surrogate
) -> tuple[list[Fidelity], np.ndarray, np.ndarray]:
    """Predicted (as the optimiser saw them) and simulated objectives; the optimum is row 0.
    A nominee optimum (simulated in an earlier refine round, so among the surrogates' training
    rows) is left out of the fidelity statistics, which then measure the front members alone."""
    names = inputs.objectives
    sims = simulated_rows(df)
    predicted = inputs.front.loc[sims.sample_id, names].to_numpy(dtype=float)
    X = sims[list(DECISION_NAMES)].to_numpy(dtype=float)
    simulated = simulated_objectives(
        names,
        ctx.policy,
        X,
        [channels(r) for _, r in sims.iterrows()],
        surrogate.time_base(ctx.policy.timing.T3),
        surrogate.hold,
        ctx.robot.pre_pressure,
    )
    measured = slice(0 if from_front(inputs) else 1, None)
    return fidelity(names, predicted[measured], simulated[measured]), predicted, simulated


def from_front(inputs: Inputs) -> bool:
    """Whether the optimum is a member of its front (not a nominee of earlier simulations)."""
    return inputs.optimum["origin"] == FRONT


def export(ctx: RobotContext, inputs: Inputs, rate: float) -> ControllerTrajectory:
    """The optimum as joint commands at ``rate`` Hz for the robot's controller."""
    X = np.array([inputs.optimum["decision"][n] for n in DECISION_NAMES])
    try:
        return controller_trajectory(ctx.policy, build_leg(ctx.robot.leg), X, rate)
    except ExportRateError as err:
        raise SimulationError("evaluate.export_rate_hz", str(err)) from None
    except ValueError as err:  # the optimum leaves the leg's reach
        raise SimulationError("optimum export", str(err)) from None


def metrics(
    params: Params,
    inputs: Inputs,
    rows: list[TableRow],
    fid: list[Fidelity],
    controller: ControllerTrajectory,
    n_fidelity: int,
    front: dict[str, Any],
    candidates: list[Candidate],
) -> dict[str, Any]:
    """The stage's metrics: Table I changes, the paper's, fidelity, the choice and the export."""

    def entry(row) -> dict:
        out = {}
        for c, _, _ in COLUMNS:
            out[c] = round(row.values[c], 4)
            out[f"{c}_change"] = round(row.change[c], 2)
        return out

    paper = {r.trajectory: r for r in table_one(PAPER_TABLE_I, "polynomial")}["optimal"]
    return {
        "robot": params.robot,
        "surface": params.surface,
        "reference": params.evaluate.reference,
        "table": {r.trajectory: entry(r) for r in rows},
        "paper_optimal_change_vs_polynomial": {c: round(paper.change[c], 2) for c, _, _ in PEAKS},
        "fidelity": {f.objective: f.as_dict() for f in fid},
        "fidelity_points": n_fidelity,
        "front_simulated": front,
        "choice": choice_summary(candidates),
        "optimum_front_row": inputs.optimum["front_row"],
        "optimum_origin": inputs.optimum[
            "origin"
        ],  # front, or the refine round it was simulated in
        "export": {
            "rows": int(controller.table.shape[0]),
            "rate_hz": params.evaluate.export_rate_hz,
            "within_joint_limits": controller.within_joint_limits,
            "peak_joint_speed": [round(float(v), 4) for v in controller.peak_joint_speed],
        },
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
    from ftfof.report.evaluation import fidelity_figure, forces_figure, jitter_figure, paths_figure
    from ftfof.report.html import figure_data_uri

    channels = {
        name: {c: np.asarray(row[c], dtype=float) for c in PLOTTED}
        for name, row in compared(df, reference).items()
    }
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
    from ftfof.report.evaluation import choice_figure

    axes = (objectives[0], objectives[1])
    columns = [TABLE_ANALOGUE.get(name) for name in axes]
    placed: dict[str, tuple[float, float]] = {}
    if None not in columns:
        table = {r.trajectory: r.values for r in rows}
        for name in (reference, table_name(PAPER_OPTIMUM)):
            if name in table:
                placed[name] = (table[name][columns[0]], table[name][columns[1]])
    return choice_figure(candidates, axes, placed)


def context(
    params: Params,
    ctx: RobotContext,
    inputs: Inputs,
    rows: list[TableRow],
    fid: list[Fidelity],
    summary: dict[str, Any],
    predicted: np.ndarray,
    simulated: np.ndarray,
    candidates: list[Candidate],
) -> dict[str, Any]:
    """The report template's values, but for the figures and the export path."""
    import exudyn

    export = summary["export"]
    return {
        "robot": ctx.name,
        "surface": params.surface,
        "models_digest": inputs.optimum["models_digest"],
        "exudyn": exudyn.__version__,
        "optimum_row": inputs.optimum["front_row"],
        "optimum_origin": inputs.optimum["origin"],
        "front_size": int((inputs.front.origin == FRONT).sum()),
        "nominees": int(((inputs.front.origin != FRONT) & (inputs.front.origin != POLISH)).sum()),
        "polished": int((inputs.front.origin == POLISH).sum()),
        "reference": params.evaluate.reference,
        "columns": [
            {
                "key": c,
                "label": label,
                **({"unit": "mm", "scale": 1e3} if unit == "m" else {"unit": unit, "scale": 1.0}),
            }
            for c, label, unit in COLUMNS
        ],
        "front_simulated": summary["front_simulated"],
        "choice": _choice_context(
            inputs.optimum["rhs"], candidates, inputs.objectives[0], summary["choice"]
        ),
        "paper_columns": [{"key": c, "label": label} for c, label, _ in PEAKS],
        "step_check": summary["step_check"],
        "film_check": summary["film_check"],
        "step_columns": [{"key": c, "label": label, "unit": unit} for c, label, unit in CHECKED],
        "step_labels": {c: label for c, label, _ in CHECKED},
        "table": [
            {"trajectory": r.trajectory, "values": r.values, "change": r.change} for r in rows
        ],
        "paper": summary["paper_optimal_change_vs_polynomial"],
        "fidelity": [{"objective": f.objective, **f.as_dict()} for f in fid],
        "front_points": len(predicted) - 1,
        "objectives": inputs.objectives,
        "optimum_predicted": predicted[0].tolist(),
        "optimum_simulated": simulated[0].tolist(),
        "pareto": PARETO,
        "training": TRAINING,
        "refinement": REFINEMENT,
        "export": {
            "rows": export["rows"],
            "rate": export["rate_hz"],
            "duration": float(ctx.policy.timing.T3),
            "leg": ctx.robot.leg.type,
            "within_limits": export["within_joint_limits"],
            "peak_speed": ", ".join(f"{v:.2f}" for v in export["peak_joint_speed"]),
        },
    }


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


@dataclass
class Evaluation:
    summary: dict[str, Any]  # the stage's metrics
    context: dict[str, Any]  # the report's values but the figures and the export path
    figures: dict[str, str]  # the figures from the simulations, as data URIs
    controller: ControllerTrajectory  # the optimum for the robot's controller


def evaluate(
    params: Params,
    ctx: RobotContext,
    inputs: Inputs,
    simulations: pd.DataFrame,
    surrogate: Surrogate,
) -> Evaluation:
    """Everything the report shows, from the re-simulations of the optimum, front and baselines."""
    cfg = params.evaluate
    at_step, fine, on_film = split_runs(simulations)
    table = ok_rows(at_step, cfg.reference)
    T3 = ctx.policy.timing.T3
    rows = table_rows(table, cfg.reference, T3)
    steps = checked_at_both_steps(params, table, fine, T3)
    films = checked_on_both_films(params, ctx, table, on_film)
    front = judged_front(ctx, table, films)
    fid, predicted, simulated = fidelity_of(inputs, table, ctx, surrogate)
    controller = export(ctx, inputs, cfg.export_rate_hz)
    n_fidelity = len(predicted) - (0 if from_front(inputs) else 1)
    candidates = rhs_candidates(inputs.optimum, inputs.objectives)
    summary = metrics(params, inputs, rows, fid, controller, n_fidelity, front, candidates)
    summary["step_check"] = None if steps is None else steps.as_dict(OPTIMUM)
    summary["film_check"] = None if films is None else films.as_dict()
    figures = simulation_figures(
        table, predicted, simulated, inputs.objectives, cfg.reference, rows, candidates
    )
    values = context(params, ctx, inputs, rows, fid, summary, predicted, simulated, candidates)
    return Evaluation(summary, values, figures, controller)
