"""Logging a surrogate as an MLflow model and registering it as a version (train's models and
refine's fine-tuned ones); apart from :mod:`ftfof.pipeline.registry`, which the stages that only
resolve versions import, so that they need not depend on the torch model's code."""

from __future__ import annotations

from pathlib import Path

from ftfof.pipeline.registry import Version, model_name, weights_tags
from ftfof.surrogate.store import PEAKS, TARGETS, weights_file


def requirements(mlflow) -> list[str]:
    """The pip requirements a logged model names: what it was made with."""
    import numpy as np
    import torch

    return [
        f"torch=={torch.__version__.split('+')[0]}",
        f"mlflow=={mlflow.__version__}",
        f"numpy=={np.__version__}",
    ]


def module_of(models_dir: Path, loss: str):
    """``loss``'s model in ``models_dir`` as a torch module (what MLflow logs), from its saved
    config and state dict."""
    import json

    import torch

    from ftfof.surrogate.model import ForceGRU, ModelConfig

    config = json.loads((models_dir / "config.json").read_text())["model"]
    model = ForceGRU(
        ModelConfig(
            hidden=config["hidden"],
            layers=config["layers"],
            dropout=config["dropout"],
            outputs=config.get("outputs", len(TARGETS)),
        )
    )
    model.load_state_dict(torch.load(models_dir / weights_file(loss), weights_only=True))
    return model.eval()


def register(
    mlflow, robot: str, loss: str, models_dir: Path, module, **log_model: object
) -> Version:
    """Log ``module`` in the active run and register it as a new version of
    ``ftfof-<robot>-<loss>``, carrying ``models_dir``'s state dict and peak models and tagged
    with their digests (what :func:`fetch_model` and :func:`promote` match on)."""
    name = model_name(robot, loss)
    files = [models_dir / weights_file(loss), models_dir / PEAKS]
    info = mlflow.pytorch.log_model(
        module,
        name="model",
        pip_requirements=requirements(mlflow),
        serialization_format="pickle",
        registered_model_name=name,
        extra_files=[str(p) for p in files if p.exists()],
        **log_model,
    )
    client, version = mlflow.MlflowClient(), str(info.registered_model_version)
    for key, value in weights_tags(models_dir, loss).items():
        client.set_model_version_tag(name, version, key, value)
    return Version(name, version)
