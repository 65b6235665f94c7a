"""The `train` run's MLflow runs: a parent opened before the training (so its duration is the
training's), a child per model, every model registered as a version (the training itself is
:mod:`ftfof.surrogate.fit`)."""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ftfof.config import Params, Train
from ftfof.digests import models_digest
from ftfof.pipeline import tracking
from ftfof.pipeline.console import progress
from ftfof.pipeline.registering import module_of, register
from ftfof.pipeline.registry import model_name
from ftfof.report import run_metrics
from ftfof.surrogate.fit import EpochReport, Training
from ftfof.surrogate.store import TARGETS, TrainingData


class TrainRun:
    """The parent run around the training: opened on entry with the params and the dataset,
    the results, children and registered versions logged by :meth:`finish`."""

    def __init__(self, params: Params, dataset_dir: Path, dataset_digest: str):
        self.params = params
        self.mlflow = tracking.setup(tracking.experiment_name(params.robot))
        self.tags = tracking.tags("train")
        self.dataset_input = tracking.dataset_input(dataset_dir / "samples.parquet")
        self.flat = tracking.run_params(
            params,
            train=params.train.model_dump(),
            dataset=params.dataset.model_dump(),
            dataset_digest=dataset_digest,
        )

    def __enter__(self) -> TrainRun:
        mlflow = self.mlflow
        self._context = mlflow.start_run(run_name="train", tags=self.tags)
        run = self._context.__enter__()
        self.started_ms = run.info.start_time
        mlflow.log_input(self.dataset_input, context="training")
        mlflow.log_params(self.flat)
        return self

    def __exit__(self, *exc) -> bool:
        return bool(self._context.__exit__(*exc))

    def finish(self, run: Training, data: TrainingData, figures: tuple[Path, ...], out: Path):
        """Metrics, figures, and one child run per loss whose model is registered as a version
        of ``ftfof-<robot>-<loss>``; the ``use`` model gets the alias."""
        from mlflow.models import infer_signature

        mlflow, cfg = self.mlflow, self.params.train
        mlflow.set_tag(tracking.MODELS_DIGEST_TAG, models_digest(out))
        mlflow.log_metrics(run_metrics.train(run.summary))
        for path in figures:
            mlflow.log_artifact(str(path), artifact_path="figures")
        example = data.inputs("validation")[:1]
        start = self.started_ms
        for r in run.results:
            child = self._child(r["kind"], start)  # side by side (train.parallel): all
            if not cfg.parallel:  # start with the parent; else one after the other
                start += int(r["seconds"] * 1000)
            with mlflow.start_run(run_id=child, nested=True):
                mlflow.log_input(self.dataset_input, context="training")
                own = {"targets": ",".join(TARGETS), "loss": r["kind"], "seed": r["seed"]}
                mlflow.log_params({**self.flat, **own})
                _log_history(mlflow, r)
                module = module_of(out, r["kind"])
                with _no_grad():
                    output = module(_tensor(example)).numpy()
                version = register(
                    mlflow,
                    self.params.robot,
                    r["kind"],
                    out,
                    module,
                    signature=infer_signature(example, output),
                    input_example=example,
                )
                if r["kind"] == cfg.use:
                    mlflow.MlflowClient().set_registered_model_alias(
                        model_name(self.params.robot, r["kind"]), cfg.alias, version.version
                    )

    def _child(self, loss: str, start_ms: int) -> str:
        """A child run for ``loss``'s model, started when its training started."""
        client = self.mlflow.MlflowClient()
        parent = self.mlflow.active_run()
        tags = {**self.tags, "loss": loss, "mlflow.parentRunId": parent.info.run_id}
        run = client.create_run(
            parent.info.experiment_id, start_time=start_ms, tags=tags, run_name=loss
        )
        return run.info.run_id


def _log_history(mlflow, result: dict) -> None:
    """Loss per epoch as stepped metrics (``loss.train``, ``loss.validation``), in batches
    MLflow accepts."""
    from mlflow.entities import Metric

    client = mlflow.MlflowClient()
    run_id = mlflow.active_run().info.run_id
    stamp = int(time.time() * 1000)
    batch = [
        Metric(run_metrics.metric_name("loss", split), v, stamp, e)
        for split in ("train", "validation")
        for e, v in enumerate(result["history"][split])
    ]
    for start in range(0, len(batch), 900):
        client.log_batch(run_id, metrics=batch[start : start + 900])
    mlflow.log_metrics(run_metrics.train_model(result))


def _no_grad():
    import torch

    return torch.no_grad()


def _tensor(array):
    import torch

    return torch.from_numpy(array)


@contextmanager
def epochs_bar(cfg: Train) -> Iterator[EpochReport]:
    """A progress bar per model, of epochs against the cap (early stopping may end one
    before it; the bar then ends at the epoch it stopped)."""
    with progress("train") as bar:
        tasks = {loss: bar.add_task(loss, total=cfg.epochs, info=loss) for loss in cfg.losses}

        def on_epoch(loss: str, epoch: int) -> None:
            bar.update(tasks[loss], completed=epoch + 1)

        yield on_epoch
        for task in bar.tasks:
            bar.update(task.id, total=task.completed)
