"""Every artefact the stages exchange: where it lives, its format and the stage that writes it,
and what each stage reads and writes. The one place a path is spelled: the stage commands take
their defaults from here, and a test holds dvc.yaml's deps and outs equal to it.

Each format has one writer, and one reader where a command reads it back (:data:`FORMATS`, as
``module:function`` so that this module imports nothing heavy: the command line reads it at
start-up).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

DATA = Path("data")  # DVC-tracked outputs
REPORTS = Path("reports")  # metrics, figures and the report, beside the data
PROFILES = Path("profiles")  # size profiles `ftfof profile` overlays on params.yaml (inputs)


@dataclass(frozen=True)
class Artefact:
    path: Path
    format: str  # a key of FORMATS
    writer: str  # the command that writes it
    part_of: str | None = None  # the artefact whose directory holds it (DVC tracks that one)


def _a(path: str, format: str, writer: str, part_of: str | None = None) -> Artefact:
    return Artefact(Path(path), format, writer, part_of)


ARTEFACTS: dict[str, Artefact] = {
    "trajectories": _a("data/trajectories.parquet", "trajectories", "sample"),
    "sample_metrics": _a("reports/sample.json", "json", "sample"),
    "sample_summary": _a("reports/summary/sample.json", "json", "sample"),
    "acquisition": _a("data/acquisition", "simulations", "acquire"),
    "acquire_metrics": _a("reports/acquire.json", "json", "acquire"),
    "acquire_summary": _a("reports/summary/acquire.json", "json", "acquire"),
    "acquire_timing": _a("reports/acquire_timing.csv", "csv", "acquire"),
    "imported": _a("data/imported", "imported_logs", "import-logs"),
    "dataset": _a("data/dataset", "dataset", "dataset"),
    "dataset_metrics": _a("reports/dataset.json", "json", "dataset"),
    "dataset_summary": _a("reports/summary/dataset.json", "json", "dataset"),
    "dataset_figure": _a("reports/dataset_samples.png", "png", "dataset"),
    "models": _a("data/models", "models", "train"),
    "train_metrics": _a("reports/train_metrics.json", "json", "train"),
    "train_summary": _a("reports/summary/train.json", "json", "train"),
    "train_loss": _a("reports/train_loss.png", "png", "train"),
    "train_predictions": _a("reports/train_predictions.png", "png", "train"),
    "optimize": _a("data/optimize", "optimum", "optimize"),
    "optimize_metrics": _a("reports/optimize.json", "json", "optimize"),
    "optimize_summary": _a("reports/summary/optimize.json", "json", "optimize"),
    "optimize_convergence": _a("reports/optimize_convergence.csv", "csv", "optimize"),
    "optimize_convergence_figure": _a("reports/optimize_convergence.png", "png", "optimize"),
    "optimize_star": _a("reports/optimize_star.png", "png", "optimize"),
    "optimize_pcp": _a("reports/optimize_pcp.png", "png", "optimize"),
    "refine": _a("data/refine", "refine_rounds", "refine"),
    "refine_models": _a("data/refine/models", "models", "refine", "refine"),
    "refine_optimize": _a("data/refine/optimize", "optimum", "refine", "refine"),
    "refine_report": _a("reports/refine.json", "refine_report", "refine"),
    "refine_summary": _a("reports/summary/refine.json", "json", "refine"),
    "refine_figure": _a("reports/refine_fidelity.png", "png", "refine"),
    "polish": _a("data/polish", "polish_rounds", "polish"),
    "polish_optimize": _a("data/polish/optimize", "optimum", "polish", "polish"),
    "polish_report": _a("reports/polish.json", "json", "polish"),
    "polish_summary": _a("reports/summary/polish.json", "json", "polish"),
    "evaluate": _a("data/evaluate", "simulations", "evaluate"),
    "report": _a("reports/evaluate.html", "html", "evaluate"),
    "metrics": _a("reports/metrics.json", "json", "evaluate"),
    "evaluate_summary": _a("reports/summary/evaluate.json", "json", "evaluate"),
    "export": _a("reports/optimum_trajectory.csv", "csv", "evaluate"),
    "calibration": _a("reports/calibration.json", "json", "calibrate"),
    "slip_logs": _a("data/slip", "slip_logs", "slip-test"),
    "identify": _a("reports/identify.json", "json", "identify"),
    "identify_outputs": _a("reports/identify", "identified_surface", "identify"),
    "identify_summary": _a("reports/summary/identify.json", "json", "identify"),
    "simulate": _a("reports/simulate", "simulation_plots", "simulate"),
    "exports": _a("reports/export", "controller_trajectory", "export"),
    "climbs": _a("reports/climb", "climb", "climb"),
    "climbs_table": _a("data/climb", "climb", "climb-table"),
    "climb_table": _a("reports/climb.json", "json", "climb-table"),
    "climb_summary": _a("reports/summary/climb.json", "json", "climb-table"),
    "slips": _a("data/slip_comparison", "climb", "slip"),
    "slip_table": _a("reports/slip.json", "json", "slip"),
    "slip_summary": _a("reports/summary/slip.json", "json", "slip"),
    "eps_study": _a("reports/eps_study.json", "json", "study eps"),
    "eps_study_figure": _a("reports/eps_study.png", "png", "study eps"),
    "study_summary": _a("reports/summary/study.json", "json", "study eps"),
    "payload": _a("reports/payload.json", "json", "study payload"),
    "payload_figure": _a("reports/payload.png", "png", "study payload"),
}

# format -> (its writer, its reader), as ``module:function``. The reader is None where no command
# reads the format back: it is for the user (metrics, timings, the report, the export).
FORMATS: dict[str, tuple[str, str | None]] = {
    "trajectories": ("ftfof.files:write_parquet", "ftfof.files:read_table"),
    "simulations": ("ftfof.pipeline.jobs:Acquisition", "ftfof.files:read_table"),
    "imported_logs": ("ftfof.files:write_parquet", "ftfof.files:read_table"),
    "dataset": ("ftfof.surrogate.store:write_dataset", "ftfof.surrogate.store:read_dataset"),
    "models": ("ftfof.surrogate.store:write_models", "ftfof.surrogate.store:load_surrogate"),
    "optimum": ("ftfof.pipeline.artefacts:write_optimum", "ftfof.pipeline.artefacts:read_optimum"),
    # a stage's working directory: its rounds or journal, and the parts the next stage reads
    "refine_rounds": ("ftfof.pipeline.refine:run", None),
    "polish_rounds": ("ftfof.pipeline.polish:run", None),
    "refine_report": ("ftfof.files:write_json", "ftfof.pipeline.artefacts:read_refine"),
    "png": ("ftfof.files:save_figure", "ftfof.pipeline.artefacts:read_figure"),
    "json": ("ftfof.files:write_json", "ftfof.pipeline.artefacts:read_json"),
    "csv": ("ftfof.files:atomic_path", None),
    "html": ("ftfof.files:atomic_path", None),
    "simulation_plots": ("ftfof.files:save_figure", None),
    # the convergence plot and the preset block, for the user (`identify --write-params` sets it)
    "identified_surface": ("ftfof.pipeline.identify:write_outputs", None),
    "slip_logs": ("ftfof.pipeline.identify:write_log", "ftfof.pipeline.identify:read_log"),
    "controller_trajectory": ("ftfof.evaluate.export:render", None),
    "climb": ("ftfof.pipeline.climb:write_climb", "ftfof.pipeline.artefacts:read_figure"),
}

# DVC stage -> (the artefacts it reads, the artefacts it writes); its command is
# :data:`ftfof.pipeline.dvcfile.STAGES`'s (the stage's name but for climb and study)
STAGES: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "sample": ((), ("trajectories", "sample_metrics", "sample_summary")),
    "acquire": (
        ("trajectories",),
        ("acquisition", "acquire_timing", "acquire_metrics", "acquire_summary"),
    ),
    "dataset": (
        ("acquisition", "imported"),
        ("dataset", "dataset_metrics", "dataset_summary", "dataset_figure"),
    ),
    "train": (
        ("dataset",),
        ("models", "train_metrics", "train_summary", "train_loss", "train_predictions"),
    ),
    "optimize": (
        ("models",),
        (
            "optimize",
            "optimize_convergence",
            "optimize_metrics",
            "optimize_summary",
            "optimize_convergence_figure",
            "optimize_star",
            "optimize_pcp",
        ),
    ),
    "refine": (
        ("dataset", "acquisition", "models", "optimize"),
        ("refine", "refine_report", "refine_summary", "refine_figure"),
    ),
    "polish": (("refine_optimize", "refine_models"), ("polish", "polish_report", "polish_summary")),
    "evaluate": (
        (
            "refine_models",
            "polish_optimize",
            "refine_report",
            "refine_figure",
            "optimize_star",
            "optimize_pcp",
            "optimize_convergence_figure",
            "train_loss",
            "train_predictions",
            "climbs_table",
            "climb_table",
            "slips",
            "slip_table",
            "eps_study",
            "eps_study_figure",
        ),
        ("evaluate", "report", "export", "metrics", "evaluate_summary"),
    ),
    "climb": (("polish_optimize",), ("climbs_table", "climb_table", "climb_summary")),
    "slip": ((), ("slips", "slip_table", "slip_summary")),
    "study": ((), ("eps_study", "eps_study_figure", "study_summary")),
    "identify": (("slip_logs",), ("identify", "identify_outputs", "identify_summary")),
}


def path(name: str) -> Path:
    """Where the artefact ``name`` lives, relative to the project root."""
    return ARTEFACTS[name].path


def placed(name: str, reports: Path, data: Path) -> Path:
    """The artefact ``name`` at the catalog's place under other ``reports`` and ``data`` folders
    (tests write into temporary ones)."""
    own = path(name)
    root, base = (reports, REPORTS) if own.is_relative_to(REPORTS) else (data, DATA)
    return Path(root) / own.relative_to(base)


def summary_beside(metrics: Path, stage: str) -> Path:
    """Where ``stage`` writes its short DVC summary when its full report goes to ``metrics``:
    at the catalog's place relative to the reports folder, wherever that folder is."""
    return placed(f"{stage}_summary", Path(metrics).parent, DATA)


def writer_of(path: Path) -> str | None:
    """The command that writes the artefact at ``path`` (a catalog path, also under another
    root), None for a path the catalog does not know: what a missing input's hint names."""
    parts = Path(path).parts
    for artefact in ARTEFACTS.values():
        own = artefact.path.parts
        if parts[-len(own) :] == own:
            return artefact.writer
    return None


def run_first(path: Path, usual: str) -> str:
    """The hint for a missing input at ``path``: the command that writes it (``usual`` where the
    catalog does not know the path)."""
    return f"run `ftfof {writer_of(path) or usual}` first"


def tracked(name: str) -> Path:
    """The path DVC tracks for ``name``: its own, or that of the directory holding it."""
    artefact = ARTEFACTS[name]
    return path(artefact.part_of) if artefact.part_of else artefact.path
