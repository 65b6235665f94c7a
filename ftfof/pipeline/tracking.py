"""MLflow conventions: where the store is, what every run is tagged with, and how a run links to
the run that made its inputs (README, Browsing runs in MLflow)."""

from __future__ import annotations

import hashlib
import os
import subprocess
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

from ftfof.pipeline import catalog, machine
from ftfof.report import run_metrics

if TYPE_CHECKING:
    from ftfof.config import Params

EXPERIMENT_PREFIX = "ftfof"
MODELS_DIGEST_TAG = "ftfof.models_digest"  # on the train run that wrote data/models
OPTIMUM_DIGEST_TAG = "ftfof.optimum_digest"  # on the optimize run that wrote data/optimize
SURROGATE_RUN_TAG = "ftfof.surrogate_run"  # on an optimize run: the train run of its models
OPTIMIZE_RUN_TAG = "ftfof.optimize_run"  # on an evaluate run: the optimize run of its optimum
# on refine, polish and evaluate runs: the registered model version (models:/<name>/<version>)
# whose surrogates found the run's optimum
MODEL_TAG = "ftfof.model"
# what the experiment is for, as MLflow names it: model training, not a GenAI app. MLflow 3.17's
# own UI reads its GenAI / Model training switch instead (docs/user-guide.md, MLflow)
KIND_TAG, KIND = "mlflow.experimentKind", "custom_model_development"
# the training data's path in the repository
DATASET_SOURCE = (catalog.path("dataset") / "samples.parquet").as_posix()


def repo_root() -> Path:
    """The DVC project root when run by DVC, else the working directory."""
    return Path(os.environ.get("DVC_ROOT", ".")).resolve()


def project_root() -> Path:
    """The repository, also when DVC runs an experiment in a temporary copy under .dvc/tmp."""
    root = repo_root()
    parts = root.parts
    if ".dvc" in parts:
        i = parts.index(".dvc")
        if parts[i + 1 : i + 3] == ("tmp", "exps"):
            return Path(*parts[:i])
    return root


def tracking_uri() -> str:
    """``MLFLOW_TRACKING_URI`` if set, else an absolute SQLite store at the repository root."""
    return os.environ.get("MLFLOW_TRACKING_URI") or f"sqlite:///{project_root() / 'mlflow.db'}"


def setup(experiment: str):
    """Import MLflow configured for this project (quietly) and select the experiment, created
    (or marked, where an earlier version made it) as a model-training one (``KIND_TAG``)."""
    os.environ.setdefault("MLFLOW_DISABLE_TELEMETRY", "true")
    os.environ.setdefault("GIT_PYTHON_REFRESH", "quiet")
    os.environ.setdefault("MLFLOW_ENABLE_ARTIFACTS_PROGRESS_BAR", "false")
    import logging

    import mlflow

    logging.getLogger("mlflow").setLevel(logging.ERROR)
    logging.getLogger("alembic").setLevel(logging.ERROR)
    mlflow.set_tracking_uri(tracking_uri())
    found = mlflow.get_experiment_by_name(experiment)
    if found is None:
        # Artifacts beside the store, whatever directory the stage runs in (dvc exp --temp);
        # a store named by MLFLOW_TRACKING_URI keeps its own default.
        env = os.environ.get("MLFLOW_TRACKING_URI")
        artifacts = None if env else (project_root() / "mlruns").as_uri()
        mlflow.create_experiment(experiment, artifact_location=artifacts, tags={KIND_TAG: KIND})
    elif KIND_TAG not in found.tags:  # made before the tag
        mlflow.MlflowClient().set_experiment_tag(found.experiment_id, KIND_TAG, KIND)
    mlflow.set_experiment(experiment)
    return mlflow


def experiment_name(robot: str) -> str:
    return f"{EXPERIMENT_PREFIX}-{robot}"


def tags(stage: str) -> dict[str, str]:
    """Provenance tags: git commit, DVC stage, experiment (set by `dvc exp run`) and the CPU.

    ``mlflow.source.name`` is the stage: MLflow would otherwise show ``__main__`` (``python -m``).
    """
    out = {
        "dvc.stage": os.environ.get("DVC_STAGE", stage),
        "git.commit": git_commit(),
        "mlflow.source.name": stage,
        "machine.cpu": machine.label(machine.describe()),
    }
    for env, key in (("DVC_EXP_NAME", "dvc.exp_name"), ("DVC_EXP_BASELINE_REV", "dvc.baseline")):
        if os.environ.get(env):
            out[key] = os.environ[env]
    return out


def git_commit() -> str:
    try:
        cmd = ["git", "rev-parse", "HEAD"]
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=10, cwd=project_root())
    except OSError:
        return "unknown"
    return out.stdout.strip() or "unknown"


def run_params(params: Params, **sections: object) -> dict[str, str]:
    """What a stage's run logs as MLflow params (:func:`ftfof.report.run_metrics.run_settings`):
    its settings ``sections``, the robot and surface, and the seeds."""
    seeds = (params.base.seed, params.search_seed)
    return run_metrics.run_settings(sections, params.robot, params.surface, *seeds)


def latest_run(mlflow, experiment: str, run_name: str, tag: str, value: str) -> str | None:
    """The latest finished run named ``run_name`` carrying ``tag = value``, if this store has one.

    Links a stage's run to the run that made its inputs (train -> models, optimize -> optimum).
    """
    runs = mlflow.search_runs(
        experiment_names=[experiment],
        filter_string=(
            f"attributes.run_name = '{run_name}' AND attributes.status = 'FINISHED' "
            f"AND tags.`{tag}` = '{value}'"
        ),
        order_by=["attributes.start_time DESC"],
        max_results=1,
        output_format="list",
    )
    return runs[0].info.run_id if runs else None


def link_note(mlflow, experiment: str, what: str, run_id: str) -> str:
    """Markdown for the run description: a link to another run of the same experiment."""
    experiment_id = mlflow.get_experiment_by_name(experiment).experiment_id
    return f"{what}: run [{run_id}](#/experiments/{experiment_id}/runs/{run_id})"


def link_tags(
    mlflow,
    experiment: str,
    source: str,
    digest_tag: str,
    digest: str,
    link_tag: str,
    what: str,
    detail: str = "",
) -> tuple[dict[str, str], str | None]:
    """Tags linking a run to the latest ``source`` run whose ``digest_tag`` is ``digest``, and
    that run's id (None when this store has none): the one way runs name their inputs' runs."""
    run_id = latest_run(mlflow, experiment, source, digest_tag, digest)
    out = {digest_tag: digest, link_tag: run_id or "unknown"}
    if run_id:
        out["mlflow.note.content"] = link_note(mlflow, experiment, what, run_id) + detail
    return out, run_id


def dataset_input(path: Path):
    """The training dataset as an MLflow dataset input: its repository path as source and its
    md5 (what DVC records for the file) as digest, so the run's Dataset column names the data."""
    from mlflow.data.dataset_source_registry import resolve_dataset_source
    from mlflow.data.meta_dataset import MetaDataset

    digest = hashlib.md5(path.read_bytes()).hexdigest()
    with warnings.catch_warnings():  # MLflow registers its local-file source twice
        warnings.simplefilter("ignore", UserWarning)
        source = resolve_dataset_source(DATASET_SOURCE)
    return MetaDataset(source, name="ftfof-dataset", digest=digest)
