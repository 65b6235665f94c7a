"""Surrogates in the MLflow model registry: one registered model per robot and loss (each a
multi-output GRU over every target).

``train`` registers every model it trains as a new version and points an alias (``champion`` by
default) at the model the optimiser is to use; ``optimize`` resolves it by that alias, so the
MLflow UI shows which version each search used. The state dict rides along in the model version
(``extra_files``) and is read with ``torch.load(weights_only=True)``: nothing is unpickled.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

from ftfof.errors import DataError
from ftfof.pipeline.digests import file_sha256
from ftfof.surrogate.store import PEAKS, weights_file


def model_name(robot: str, loss: str) -> str:
    """The registered model's name, e.g. ``ftfof-mst_m3f-dilate``."""
    return f"ftfof-{robot}-{loss}"


@dataclass(frozen=True)
class RegisteredWeights:
    """One model version resolved by alias, and where its state dict was fetched to."""

    name: str
    version: str
    run_id: str
    path: Path

    @property
    def uri(self) -> str:
        return f"models:/{self.name}/{self.version}"


def fetch_model(
    mlflow, robot: str, loss: str, alias: str, models_dir: Path, into: Path | None = None
) -> RegisteredWeights:
    """Resolve ``models:/ftfof-<robot>-<loss>@<alias>`` and download its weights, which must be
    byte-identical to the file DVC tracks in ``models_dir`` (and so must its peak models), so the
    registry and the pipeline cannot disagree about which surrogate a search used."""
    from mlflow.exceptions import MlflowException

    client = mlflow.MlflowClient()
    into = into or Path(tempfile.mkdtemp(prefix="ftfof-models-"))
    name = model_name(robot, loss)
    uri = f"models:/{name}@{alias}"
    try:
        version = client.get_model_version_by_alias(name, alias)
    except MlflowException:
        raise DataError(
            uri,
            f"not in the MLflow registry at {mlflow.get_tracking_uri()} (run `ftfof train`)",
        ) from None
    local = Path(mlflow.artifacts.download_artifacts(artifact_uri=uri, dst_path=str(into)))
    path = local / "extra_files" / weights_file(loss)
    tracked = models_dir / weights_file(loss)
    if not path.is_file():
        raise DataError(uri, f"model version {version.version} carries no {path.name}")
    for carried, kept in ((path, tracked), (path.parent / PEAKS, models_dir / PEAKS)):
        if carried.is_file() != kept.is_file() or (
            kept.is_file() and file_sha256(carried) != file_sha256(kept)
        ):
            raise DataError(
                uri,
                f"version {version.version} differs from {kept} "
                "(models trained elsewhere? re-run `ftfof train`)",
            )
    return RegisteredWeights(name, str(version.version), version.run_id, path)
