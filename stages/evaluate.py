"""Stage `evaluate`: re-simulate the optimum, front members and baselines; write the report.

The simulations are an acquisition job under ``data/evaluate/`` (resumable like `acquire`); the
Table I analogue and every figure come from them, never from the surrogates, whose predictions are
only compared with them (surrogate fidelity).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import numpy as np
import typer

from stages.common import ParamsOption, atomic_path, console, stage, write_json

if TYPE_CHECKING:
    import pandas as pd

    from ftfof.evaluate.export import ControllerTrajectory
    from ftfof.evaluate.fidelity import Fidelity
    from ftfof.evaluate.table import TableRow
    from stages.acquisition import Acquisition

OPTIMIZE = Path("data/optimize")
MODELS = Path("data/models")
OUT = Path("data/evaluate")
REPORT = Path("reports/evaluate.html")
METRICS = Path("reports/metrics.json")
EXPORT = Path("reports/optimum_trajectory.csv")
FIGURES = Path("reports")
PARETO = (
    ("optimize_star.png", "Pareto front, star coordinates (cf. FTFOF Fig. 10)"),
    ("optimize_pcp.png", "Pareto front, parallel coordinates"),
    ("optimize_convergence.png", "NSGA-II convergence: normalised hypervolume, feasible count"),
)
TRAINING = (
    ("train_loss.png", "Training and validation loss per model (cf. FTFOF Fig. 8)"),
    ("train_predictions.png", "Validation predictions against simulation (cf. FTFOF Fig. 9)"),
)
OPTIMUM = "optimum"
PLOTTED = ("t", "x_cmd", "z_cmd", "Fd", "Fp", "body_acc")  # channels the report's figures use


@dataclass
class Inputs:
    """What `optimize` left: the chosen row and the front it came from, checked against params."""

    optimum: dict
    front: pd.DataFrame  # indexed by front row
    objectives: list[str]
    digest: str


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    optimize: Annotated[Path, typer.Option(help="The optimize stage's directory.")] = OPTIMIZE,
    models: Annotated[Path, typer.Option(help="Trained surrogate directory.")] = MODELS,
    figures: Annotated[Path, typer.Option(help="Where the train/optimize PNGs are.")] = FIGURES,
    out: Annotated[Path, typer.Option(help="Simulations of this evaluation.")] = OUT,
    report: Annotated[Path, typer.Option(help="Self-contained HTML report.")] = REPORT,
    metrics: Annotated[Path, typer.Option(help="Metrics JSON.")] = METRICS,
    export: Annotated[Path, typer.Option(help="Controller CSV of the optimum.")] = EXPORT,
    workers: Annotated[int | None, typer.Option(help="Override acquire.workers.")] = None,
) -> None:
    """Re-simulate the optimum against the common trajectories; report, metrics, export."""
    from ftfof.errors import DataError
    from stages.params import load_params
    from stages.robot import robot_context
    from stages.surrogates import load_surrogate, models_digest

    params = load_params(params_path)
    ctx = robot_context(params)
    inputs = _read_inputs(optimize, ctx.name)
    if inputs.optimum["models_digest"] != models_digest(models):
        raise DataError(str(optimize), f"was optimised on other models than {models} (re-run it)")
    surrogate = load_surrogate(models)
    pictures = {key: _picture(figures / key) for key, _ in (*PARETO, *TRAINING)}
    front_rows = _front_sample(inputs, params.evaluate.front_points)
    job = _job(params, ctx, out, inputs, front_rows)
    cfg = params.acquire
    todo = job.remaining()
    console.print(
        f"evaluate {ctx.name} on {params.surface}: {len(job.specs)} simulations "
        f"(optimum, {len(front_rows)} front members, baselines), {len(todo)} to run"
    )
    wall = job.simulate(
        todo, cfg.workers if workers is None else workers, cfg.scheduler, "evaluate"
    )
    job.finish(wall, len(todo))
    table = _ok_rows(job, params.evaluate.reference)
    rows = _table_one(table, params.evaluate.reference)
    fidelity, predicted, simulated = _fidelity(inputs, table, ctx, surrogate)
    controller = _export(ctx, inputs, params.evaluate.export_rate_hz)
    summary = _metrics(params, inputs, rows, fidelity, controller, len(predicted))
    pictures.update(_simulation_figures(table, predicted, simulated, inputs.objectives))
    context = _context(params, ctx, inputs, rows, fidelity, summary, predicted, simulated)
    context.update(figures=pictures, export_path=str(export))
    _write(controller, export, summary, metrics, context, report)
    _track(params, ctx.name, inputs, summary, (report, export, metrics))
    opt = summary["table"][OPTIMUM]
    ref = params.evaluate.reference
    console.print(
        f"optimum vs {ref}: detachment {opt['peak_detachment_change']:+.1f} %, pre-pressure "
        f"{opt['peak_pre_pressure_change']:+.1f} %, jitter {opt['peak_body_acc_change']:+.1f} % "
        f"-> {report}"
    )


def _read_inputs(directory: Path, robot: str) -> Inputs:
    import pyarrow.parquet as pq

    from ftfof.errors import DataError
    from stages.optimize import optimum_digest

    path = directory / "optimum.json"
    if not path.exists() or not (directory / "front.parquet").exists():
        raise DataError(str(directory), "no optimum (run `ftfof optimize` first)")
    try:
        optimum = json.loads(path.read_text())
        front = pq.read_table(directory / "front.parquet")
        meta = json.loads(front.schema.metadata[b"ftfof"])
    except (ValueError, KeyError, OSError) as err:
        raise DataError(str(directory), f"unreadable optimize output ({err})") from None
    if optimum.get("robot") != robot or meta.get("robot") != robot:
        raise DataError(
            str(directory),
            f"holds an optimum for {optimum.get('robot')!r} but params select {robot!r} "
            "(re-run `ftfof optimize`)",
        )
    frame = front.to_pandas().set_index("row")
    return Inputs(optimum, frame, list(meta["objectives"]), optimum_digest(directory))


def _picture(path: Path) -> str:
    from ftfof.errors import DataError
    from ftfof.report.html import png_data_uri

    if not path.exists():
        raise DataError(str(path), "figure missing (run the stage that writes it)")
    try:
        return png_data_uri(path.read_bytes())
    except ValueError:
        raise DataError(str(path), "is not a PNG image") from None


def _front_sample(inputs: Inputs, k: int) -> list[int]:
    """``k`` front rows spread evenly along the priority-sorted front, the optimum left out."""
    front = inputs.front
    rows = front.index[front.recheck_feasible & (front.index != inputs.optimum["front_row"])]
    rows = rows.to_numpy()
    if k == 0 or rows.size == 0:
        return []
    picks = np.unique(np.round(np.linspace(0, rows.size - 1, min(k, rows.size))).astype(int))
    return [int(r) for r in rows[picks]]


def _decision(inputs: Inputs, row: int) -> np.ndarray:
    from ftfof.trajectory.bezier import DECISION_NAMES

    return inputs.front.loc[row, list(DECISION_NAMES)].to_numpy(dtype=float)


def _job(params, ctx, out: Path, inputs: Inputs, front_rows: list[int]) -> Acquisition:
    from ftfof.sim.spec import Bench
    from ftfof.trajectory.baselines import common_trajectories
    from stages.acquisition import Acquisition

    bench = Bench(
        ctx.robot, params.selected_surface, params.platform, params.acquire, params.base.seed
    )
    chosen = inputs.optimum["front_row"]
    specs, controls = [], {}
    for source, row in [(OPTIMUM, chosen), *(("front", r) for r in front_rows)]:
        X = _decision(inputs, row)
        spec = bench.bezier(source, row, X)
        specs.append(spec)
        controls[spec.key] = X
    for name, traj in common_trajectories(ctx.policy, params.baselines, params.base.seed).items():
        specs.append(bench.analytic(f"baseline:{name}", 0, traj))
    return Acquisition.start(
        params, ctx, out, specs, controls, {"optimum": inputs.digest, "front_rows": front_rows}
    )


def _ok_rows(job: Acquisition, reference: str):
    """The job's table (pandas), with a clear error when the optimum or the reference failed."""
    import pyarrow.parquet as pq

    from ftfof.errors import SimulationError
    from stages.acquisition import FINAL

    df = pq.read_table(job.out / FINAL).to_pandas()
    for source in (OPTIMUM, f"baseline:{reference}"):
        row = df[df.source == source]
        if row.empty or row.iloc[0].status != "ok":
            error = row.iloc[0].error if not row.empty else "missing"
            raise SimulationError(source, f"re-simulation failed: {error}")
    return df[df.status == "ok"]


def _compared(df) -> dict[str, object]:
    """The baselines then the optimum, by display name: the rows of the table and the figures."""
    sources = [s for s in df.source if s.startswith("baseline:")] + [OPTIMUM]
    return {s.removeprefix("baseline:"): df[df.source == s].iloc[0] for s in sources}


def _table_one(df, reference: str) -> list[TableRow]:
    from ftfof.evaluate.table import PEAKS, table_one

    peaks = {name: {c: float(row[c]) for c, _, _ in PEAKS} for name, row in _compared(df).items()}
    return table_one(peaks, reference)


def _forces(row):
    from ftfof.evaluate.fidelity import SimulatedForces

    return SimulatedForces(*(np.asarray(row[c], dtype=float) for c in ("t", "Fd", "Fp")))


def _fidelity(inputs: Inputs, df, ctx, surrogate) -> tuple[list[Fidelity], np.ndarray, np.ndarray]:
    """Predicted (as the optimiser saw them) and simulated objectives; the optimum is row 0."""
    from ftfof.evaluate.fidelity import fidelity, simulated_objectives
    from ftfof.trajectory.bezier import DECISION_NAMES

    names = inputs.objectives
    sims = df[df.source.isin([OPTIMUM, "front"])]
    sims = sims.assign(first=sims.source != OPTIMUM).sort_values(["first", "sample_id"])
    predicted = inputs.front.loc[sims.sample_id, names].to_numpy(dtype=float)
    X = sims[list(DECISION_NAMES)].to_numpy(dtype=float)
    simulated = simulated_objectives(
        names,
        ctx.policy,
        X,
        [_forces(r) for _, r in sims.iterrows()],
        surrogate.time_base(ctx.policy.timing.T3),
        surrogate.hold,
        ctx.robot.pre_pressure,
    )
    return fidelity(names, predicted, simulated), predicted, simulated


def _export(ctx, inputs: Inputs, rate: float) -> ControllerTrajectory:
    from ftfof.errors import SimulationError
    from ftfof.evaluate.export import ExportRateError, controller_trajectory
    from ftfof.kinematics.legs import build_leg
    from ftfof.trajectory.bezier import DECISION_NAMES

    X = np.array([inputs.optimum["decision"][n] for n in DECISION_NAMES])
    try:
        return controller_trajectory(ctx.policy, build_leg(ctx.robot.leg), X, rate)
    except ExportRateError as err:
        raise SimulationError("evaluate.export_rate_hz", str(err)) from None
    except ValueError as err:  # the optimum leaves the leg's reach
        raise SimulationError("optimum export", str(err)) from None


def _metrics(params, inputs, rows, fidelity, controller, n_fidelity) -> dict:
    from ftfof.evaluate.table import PAPER_TABLE_I, PEAKS, table_one

    def entry(row) -> dict:
        out = {}
        for c, _, _ in PEAKS:
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
        "fidelity": {f.objective: f.as_dict() for f in fidelity},
        "fidelity_points": n_fidelity,
        "optimum_front_row": inputs.optimum["front_row"],
        "export": {
            "rows": int(controller.table.shape[0]),
            "rate_hz": params.evaluate.export_rate_hz,
            "within_joint_limits": controller.within_joint_limits,
            "peak_joint_speed": [round(float(v), 4) for v in controller.peak_joint_speed],
        },
    }


def _simulation_figures(df, predicted, simulated, objectives) -> dict[str, str]:
    """Fig. 11, 12, 14 from the simulated channels of the optimum and baselines; fidelity."""
    from ftfof.report.evaluation import fidelity_figure, forces_figure, jitter_figure, paths_figure
    from ftfof.report.html import figure_data_uri

    channels = {
        name: {c: np.asarray(row[c], dtype=float) for c in PLOTTED}
        for name, row in _compared(df).items()
    }
    return {
        "paths": figure_data_uri(paths_figure(channels, OPTIMUM)),
        "forces": figure_data_uri(forces_figure(channels, OPTIMUM)),
        "jitter": figure_data_uri(jitter_figure(channels, OPTIMUM)),
        "fidelity": figure_data_uri(fidelity_figure(objectives, predicted, simulated, 0)),
    }


def _context(params, ctx, inputs, rows, fidelity, summary, predicted, simulated) -> dict:
    """The report template's values, but for the figures and the export path."""
    import exudyn

    from ftfof.evaluate.table import PEAKS

    export = summary["export"]
    return {
        "robot": ctx.name,
        "surface": params.surface,
        "models_digest": inputs.optimum["models_digest"],
        "exudyn": exudyn.__version__,
        "optimum_row": inputs.optimum["front_row"],
        "front_size": len(inputs.front),
        "reference": params.evaluate.reference,
        "columns": [{"key": c, "label": label, "unit": unit} for c, label, unit in PEAKS],
        "table": [
            {"trajectory": r.trajectory, "values": r.values, "change": r.change} for r in rows
        ],
        "paper": summary["paper_optimal_change_vs_polynomial"],
        "fidelity": [{"objective": f.objective, **f.as_dict()} for f in fidelity],
        "front_points": len(predicted) - 1,
        "objectives": inputs.objectives,
        "optimum_predicted": predicted[0].tolist(),
        "optimum_simulated": simulated[0].tolist(),
        "pareto": PARETO,
        "training": TRAINING,
        "export": {
            "rows": export["rows"],
            "rate": export["rate_hz"],
            "duration": float(ctx.policy.timing.T3),
            "leg": ctx.robot.leg.type,
            "within_limits": export["within_joint_limits"],
            "peak_speed": ", ".join(f"{v:.2f}" for v in export["peak_joint_speed"]),
        },
    }


def _write(controller, export: Path, summary: dict, metrics: Path, context: dict, report: Path):
    from ftfof.report.html import render

    html = render(context)
    with atomic_path(export) as tmp:
        header = ",".join(controller.columns)
        np.savetxt(tmp, controller.table, delimiter=",", header=header, comments="", fmt="%.9g")
    write_json(metrics, summary)
    with atomic_path(report) as tmp:
        tmp.write_text(html, encoding="utf-8")


def _track(params, robot: str, inputs: Inputs, summary: dict, artifacts: tuple[Path, ...]):
    """An `evaluate` run with the table and fidelity as metrics, linked to its optimize run."""
    from stages import tracking

    experiment = tracking.experiment_name(robot)
    mlflow = tracking.setup(experiment)
    source = tracking.latest_run(
        mlflow, experiment, "optimize", tracking.OPTIMUM_DIGEST_TAG, inputs.digest
    )
    tags = {
        **tracking.tags("evaluate"),
        tracking.OPTIMUM_DIGEST_TAG: inputs.digest,
        "ftfof.optimize_run": source or "unknown",
    }
    if source:
        tags["mlflow.note.content"] = tracking.link_note(mlflow, experiment, "Optimum", source)
    metrics = {
        f"{name}.{key}": value
        for name, row in summary["table"].items()
        for key, value in row.items()
    }
    for objective, values in summary["fidelity"].items():
        for key, value in values.items():
            if value == value:  # MLflow rejects NaN
                metrics[f"fidelity.{objective}.{key}"] = float(value)
    with mlflow.start_run(run_name="evaluate", tags=tags):
        mlflow.log_params(
            tracking.flatten(
                {
                    "evaluate": params.evaluate.model_dump(),
                    "robot": robot,
                    "surface": params.surface,
                }
            )
        )
        mlflow.log_metrics(metrics)
        for path in artifacts:
            mlflow.log_artifact(str(path), artifact_path="report")
