"""The `train` run's MLflow runs: a parent per invocation, a child per model, every model
registered as a version (the training itself is :mod:`ftfof.surrogate.fit`)."""

from __future__ import annotations

import time
from pathlib import Path

from ftfof.config import Params, Train
from ftfof.digests import models_digest
from ftfof.pipeline import tracking
from ftfof.pipeline.registry import model_name, weights_tags
from ftfof.surrogate.fit import Training
from ftfof.surrogate.store import PEAKS, TARGETS, TrainingData, weights_file


def track(
    params: Params,
    run: Training,
    data: TrainingData,
    figures: tuple[Path, ...],
    out: Path,
    dataset_dir: Path,
) -> None:
    """One parent run per invocation, a child per loss; every model is registered as a version of
    ``ftfof-<robot>-<loss>``, and the ``use`` model gets the alias."""
    import numpy as np
    import torch

    mlflow = tracking.setup(tracking.experiment_name(params.robot))
    from mlflow.models import infer_signature

    tags = tracking.tags("train")
    parent_tags = {**tags, tracking.MODELS_DIGEST_TAG: models_digest(out)}
    dataset_input = tracking.dataset_input(dataset_dir / "samples.parquet")
    cfg = params.train
    example = data.inputs("validation")[:1]
    requirements = [
        f"torch=={torch.__version__.split('+')[0]}",
        f"mlflow=={mlflow.__version__}",
        f"numpy=={np.__version__}",
    ]
    flat = tracking.run_params(
        params,
        train=cfg.model_dump(),
        dataset=params.dataset.model_dump(),
        dataset_digest=data.metadata_digest,
    )
    with mlflow.start_run(run_name="train", tags=parent_tags):
        mlflow.log_input(dataset_input, context="training")
        mlflow.log_params(flat)
        mlflow.log_metric("wall_seconds", run.summary["wall_seconds"])
        mlflow.log_metrics(
            {
                f"peak_{target}_{model}_{k}": v
                for target, entry in run.summary["peaks"].items()
                for model in ("gp", "gru")
                for k, v in entry[model].items()
                if v == v
            }
        )
        for path in figures:
            mlflow.log_artifact(str(path), artifact_path="figures")
        for r in run.results:
            with mlflow.start_run(
                run_name=r["kind"], nested=True, tags={**tags, "loss": r["kind"]}
            ):
                mlflow.log_input(dataset_input, context="training")
                targets = ",".join(TARGETS)
                mlflow.log_params(
                    {**flat, "targets": targets, "loss": r["kind"], "seed": r["seed"]}
                )
                _log_history(mlflow, r)
                model, output = _model_output(r, cfg, example)
                name = model_name(params.robot, r["kind"])
                info = mlflow.pytorch.log_model(
                    model,
                    name="model",
                    signature=infer_signature(example, output),
                    input_example=example,
                    pip_requirements=requirements,
                    serialization_format="pickle",
                    registered_model_name=name,
                    extra_files=[
                        str(p) for p in (out / weights_file(r["kind"]), out / PEAKS) if p.exists()
                    ],
                )
                client, version = mlflow.MlflowClient(), str(info.registered_model_version)
                for key, value in weights_tags(out, r["kind"]).items():
                    client.set_model_version_tag(name, version, key, value)
                if r["kind"] == cfg.use:
                    client.set_registered_model_alias(name, cfg.alias, version)


def _log_history(mlflow, result: dict) -> None:
    """Loss per epoch as stepped metrics, in batches MLflow accepts."""
    from mlflow.entities import Metric

    client = mlflow.MlflowClient()
    run_id = mlflow.active_run().info.run_id
    stamp = int(time.time() * 1000)
    batch = [
        Metric(f"{split}_loss", v, stamp, e)
        for split in ("train", "validation")
        for e, v in enumerate(result["history"][split])
    ]
    for start in range(0, len(batch), 900):
        client.log_batch(run_id, metrics=batch[start : start + 900])
    mlflow.log_metrics(
        {f"val_{t}_{k}": v for t, m in result["metrics"].items() for k, v in m.items()}
    )
    mlflow.log_metric("best_epoch", result["history"]["best_epoch"])


def _model_output(result: dict, cfg: Train, example):
    """The trained model as a torch module and its output on ``example`` (for the signature)."""
    import torch

    from ftfof.surrogate.model import ForceGRU, ModelConfig

    model = ForceGRU(
        ModelConfig(hidden=cfg.hidden, layers=cfg.layers, dropout=cfg.dropout, outputs=len(TARGETS))
    )
    model.load_state_dict({k: torch.from_numpy(v) for k, v in result["state"].items()})
    model.eval()
    with torch.no_grad():
        return model, model(torch.from_numpy(example)).numpy()
