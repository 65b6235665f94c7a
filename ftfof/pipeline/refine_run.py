"""The `refine` stage's MLflow runs: a parent opened before the first round and a child per
round opened when the round starts, so their durations are the work's; linked to the runs that
made their models and fronts (train and optimize for the first round, the previous round after).
The final models are registered as a version unless a version already holds them (no round
changed train's)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ftfof.config import Params
from ftfof.digests import models_digest
from ftfof.pipeline import tracking
from ftfof.pipeline.artefacts import optimum_digest
from ftfof.pipeline.registering import module_of, register
from ftfof.pipeline.registry import Version, registered, used_loss
from ftfof.report import run_metrics


class RefineRun:
    """The parent run, its rounds' child runs and the registered final model."""

    def __init__(self, params: Params, models: Path, optimize: Path, out: Path):
        """``models`` and ``optimize``: what refine starts from; ``out``: its directory."""
        self.params, self.out = params, out
        experiment = tracking.experiment_name(params.robot)
        self.mlflow = mlflow = tracking.setup(experiment)

        def find(source: str, tag: str, digest: str) -> str:
            return tracking.latest_run(mlflow, experiment, source, tag, digest) or "unknown"

        train = find("train", tracking.MODELS_DIGEST_TAG, models_digest(models))
        optimize = find("optimize", tracking.OPTIMUM_DIGEST_TAG, optimum_digest(optimize))
        self.links = {tracking.SURROGATE_RUN_TAG: train, tracking.OPTIMIZE_RUN_TAG: optimize}
        self.tags = tracking.tags("refine")
        self.settings = tracking.run_params(params, refine=params.refine.model_dump())

    def __enter__(self) -> RefineRun:
        self._context = self.mlflow.start_run(run_name="refine", tags={**self.tags, **self.links})
        self._context.__enter__()
        self.mlflow.log_params(self.settings)
        return self

    def __exit__(self, *exc) -> bool:
        return bool(self._context.__exit__(*exc))

    @contextmanager
    def round(self, k: int) -> Iterator[None]:
        """Round ``k``'s child run, open while the round runs."""
        mlflow = self.mlflow
        tags = {**self.tags, **self.links, "round": str(k)}
        with mlflow.start_run(run_name=f"refine-{k}", nested=True, tags=tags):
            mlflow.log_params({**self.settings, "round": str(k)})
            yield

    def round_done(self, record: dict[str, Any], rdir: Path) -> None:
        """In the round's run: its metrics, and its models (the next round links to it)."""
        mlflow = self.mlflow
        mlflow.log_metrics(run_metrics.refine_round(record))
        if (rdir / "models").is_dir():
            mlflow.log_artifacts(str(rdir / "models"), artifact_path="models")
            mlflow.set_tag(tracking.MODELS_DIGEST_TAG, models_digest(rdir / "models"))
            mlflow.set_tag(tracking.OPTIMUM_DIGEST_TAG, optimum_digest(rdir / "optimize"))
            run_id = mlflow.active_run().info.run_id
            self.links = {tracking.SURROGATE_RUN_TAG: run_id, tracking.OPTIMIZE_RUN_TAG: run_id}

    def finish(self, report: dict[str, Any], artifacts: tuple[Path, ...]) -> Version:
        """The parent's metrics, artifacts and digests, and the final models' version."""
        mlflow, out = self.mlflow, self.out
        name = run_metrics.metric_name
        mlflow.log_metrics(
            {
                name("refine", "rounds"): len(report["rounds"]),
                name("time", "seconds"): report["seconds"],
            }
        )
        for path in artifacts:
            mlflow.log_artifact(str(path), artifact_path="report")
        mlflow.set_tags(
            {
                tracking.MODELS_DIGEST_TAG: models_digest(out / "models"),
                tracking.OPTIMUM_DIGEST_TAG: optimum_digest(out / "optimize"),
            }
        )
        robot, use = self.params.robot, used_loss(out / "models")
        version = registered(mlflow, robot, use, out / "models")
        if version is None:  # fine-tuned: a new version
            version = register(mlflow, robot, use, out / "models", module_of(out / "models", use))
        mlflow.set_tag(tracking.MODEL_TAG, version.uri)
        return version
