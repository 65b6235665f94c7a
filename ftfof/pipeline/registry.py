"""Surrogates in the MLflow model registry: one registered model per robot and loss (each a
multi-output GRU over every target).

``train`` registers every model it trains as a new version and points an alias (``champion`` by
default) at the model the optimiser is to use; ``optimize`` resolves it by that alias, so the
MLflow UI shows which version each search used. ``refine`` registers its fine-tuned models as a
new version (unless no round changed them), and ``evaluate`` moves the alias to the version that
found the optimum it reports (:func:`promote`): after a full run, ``champion`` names the model
that produced the answer. The state dict rides along in the model version
(``extra_files``) and is read with ``torch.load(weights_only=True)``: nothing is unpickled.

Every version is tagged with the SHA-256 of its weights and peak models. Where the alias names
another version than the one holding ``data/models`` (``evaluate`` moved it to refine's
fine-tuned version, or DVC restored an earlier ``train`` from its run cache without running it),
``optimize`` moves the alias back to the version whose tags match the tracked files, instead of
refusing them.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

from ftfof.digests import file_sha256, models_digest
from ftfof.errors import DataError
from ftfof.surrogate.store import PEAKS, weights_file


def model_name(robot: str, loss: str) -> str:
    """The registered model's name, e.g. ``ftfof-mst_m3f-dilate``."""
    return f"ftfof-{robot}-{loss}"


WEIGHTS_TAG = "ftfof.weights_sha256"
PEAKS_TAG = "ftfof.peaks_sha256"


@dataclass(frozen=True)
class RegisteredWeights:
    """One model version resolved by alias, and where its state dict was fetched to."""

    name: str
    version: str
    run_id: str
    path: Path
    moved_from: str | None = None  # the version the alias named before it was moved back

    @property
    def uri(self) -> str:
        return f"models:/{self.name}/{self.version}"


def weights_tags(models_dir: Path, loss: str) -> dict[str, str]:
    """The digests a version of ``loss``'s model trained into ``models_dir`` is tagged with."""
    peaks = models_dir / PEAKS
    return {
        WEIGHTS_TAG: file_sha256(models_dir / weights_file(loss)),
        PEAKS_TAG: file_sha256(peaks) if peaks.is_file() else "none",
    }


@dataclass(frozen=True)
class Version:
    """A registered model version: ``models:/<name>/<version>``."""

    name: str
    version: str

    @property
    def uri(self) -> str:
        return f"models:/{self.name}/{self.version}"


def used_loss(models_dir: Path) -> str:
    """The loss of the model the searches in ``models_dir`` use (its config's ``use``)."""
    import json

    return json.loads((models_dir / "config.json").read_text())["use"]


def model_record(models_dir: Path) -> dict[str, str]:
    """What reports/metrics.json records of the surrogates that found the optimum: the loss, the
    digest of their directory and the SHA-256 of the weights and peak models (the tags that
    name their registered version)."""
    loss = used_loss(models_dir)
    tags = weights_tags(models_dir, loss)
    return {
        "loss": loss,
        "models_digest": models_digest(models_dir),
        "weights_sha256": tags[WEIGHTS_TAG],
        "peaks_sha256": tags[PEAKS_TAG],
    }


def registered(mlflow, robot: str, loss: str, models_dir: Path) -> Version | None:
    """The newest version of ``ftfof-<robot>-<loss>`` holding ``models_dir``'s files (None if
    none does)."""
    name = model_name(robot, loss)
    version = _newest_tagged(mlflow.MlflowClient(), name, weights_tags(models_dir, loss))
    return None if version is None else Version(name, str(version.version))


def promote(mlflow, robot: str, loss: str, alias: str, models_dir: Path) -> Version | None:
    """Point ``alias`` at the version holding ``models_dir``'s files: the model that produced
    the answer. None (the alias unmoved) where no version holds them."""
    version = registered(mlflow, robot, loss, models_dir)
    if version is not None:
        mlflow.MlflowClient().set_registered_model_alias(version.name, alias, version.version)
    return version


def fetch_model(
    mlflow, robot: str, loss: str, alias: str, models_dir: Path, into: Path | None = None
) -> RegisteredWeights:
    """Resolve ``models:/ftfof-<robot>-<loss>@<alias>`` and download its weights, which must be
    byte-identical to the file DVC tracks in ``models_dir`` (and so must its peak models), so the
    registry and the pipeline cannot disagree about which surrogate a search used. Where the alias
    names another version but a registered one is tagged with the tracked files' digests (DVC
    restored an earlier ``train``), the alias moves back to it."""
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
    moved_from = None
    tracked = models_dir / weights_file(loss)
    if tracked.is_file() and not _tagged_with(version, tags := weights_tags(models_dir, loss)):
        twin = _newest_tagged(client, name, tags)
        if twin is not None:
            moved_from, version = str(version.version), twin
    source = f"models:/{name}/{version.version}"
    local = Path(mlflow.artifacts.download_artifacts(artifact_uri=source, dst_path=str(into)))
    path = local / "extra_files" / weights_file(loss)
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
    if moved_from is not None:  # only once its files are verified: a failed stage moves nothing
        client.set_registered_model_alias(name, alias, version.version)
    return RegisteredWeights(name, str(version.version), version.run_id, path, moved_from)


def _tagged_with(version, tags: dict[str, str]) -> bool:
    return all(version.tags.get(k) == v for k, v in tags.items())


def _newest_tagged(client, name: str, tags: dict[str, str]):
    """The newest version of ``name`` carrying every tag of ``tags`` (None if none does)."""
    matching = [
        v for v in client.search_model_versions(f"name = '{name}'") if _tagged_with(v, tags)
    ]
    return max(matching, key=lambda v: int(v.version), default=None)
