"""Stage `train`: outputs loadable with weights_only, metrics and figures, MLflow runs."""

import json

import pytest
import torch

from ftfof.data.targets import TARGETS
from ftfof.pipeline import machine
from ftfof.surrogate.store import load_surrogate

pytestmark = pytest.mark.integration


def test_models_load_with_weights_only(trained):
    tmp, _, _ = trained
    for loss in ("dilate", "mse"):
        state = torch.load(tmp / "models" / f"surrogate_{loss}.pt", weights_only=True)
        assert "gru.weight_ih_l0" in state and state["head.weight"].shape[0] == len(TARGETS)
    config = json.loads((tmp / "models" / "config.json").read_text())
    assert config["use"] == "mse" and config["seq_len"] == 24  # params.yaml: train.use
    assert config["trained"] == list(TARGETS)  # the fake acquisition carries the film channel
    surrogate = load_surrogate(tmp / "models")
    assert surrogate.seq_len == 24 and surrogate.trained == TARGETS


def test_metrics_and_figures(trained):
    tmp, _, _ = trained
    metrics = json.loads((tmp / "models.json").read_text())
    for loss in ("dilate", "mse"):
        m = metrics[loss]
        assert m["epoch_cap"] == 2 and 0 <= m["best_epoch"] < m["epochs"] <= 2
        assert set(m["targets"]) == set(TARGETS)
        for target in TARGETS:
            assert {
                "n",
                "mse",
                "dtw",
                "peak_error_median",
                "peak_error_p90",
                "peak_time_error_median",
            } <= set(m["targets"][target])
    for png in ("models_loss.png", "models_pred.png"):
        assert (tmp / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # whose weights these are: the CPU and the libraries that decide the bits
    assert metrics["machine"] == machine.describe()


def test_mlflow_holds_the_parent_and_child_runs_with_params_metrics_models_and_tags(trained):
    tmp, uri, data = trained
    import mlflow

    client = mlflow.MlflowClient(tracking_uri=uri)
    experiment = client.get_experiment_by_name("ftfof-mst_m3f")
    runs = client.search_runs([experiment.experiment_id])
    parent = [r for r in runs if r.info.run_name == "train"]
    assert len(parent) == 1
    p = parent[0]
    # other stage tests share the store (refine has child runs too)
    children = [r for r in runs if r.data.tags.get("mlflow.parentRunId") == p.info.run_id]
    assert len(children) == 2  # one multi-output model per loss
    for key in (
        "train.hidden",
        "train.alpha",
        "train.gamma",
        "train.lr",
        "dataset.seq_len",
        "robot",
        "surface",
    ):
        assert key in p.data.params, key
    assert p.data.tags["dvc.stage"] == "train" and p.data.tags["dvc.exp_name"] == "test-exp"
    assert len(p.data.tags["git.commit"]) >= 7
    assert p.data.tags["machine.cpu"] == machine.label(machine.describe())
    figures = {a.path for a in client.list_artifacts(p.info.run_id, "figures")}
    assert figures == {"figures/models_loss.png", "figures/models_pred.png"}
    # the run spans the training (it was opened before it), and each child its model's training
    wall = json.loads((tmp / "models.json").read_text())["wall_seconds"]
    assert p.info.end_time - p.info.start_time >= 1000 * wall
    assert p.data.metrics["time.seconds"] == wall
    for child in children:
        assert child.info.start_time >= p.info.start_time and child.info.status == "FINISHED"
        assert child.info.end_time - child.info.start_time >= 1000 * child_seconds(tmp, child)
    for child in children:
        assert child.data.params["train.epochs"] == str(data["train"]["epochs"])
        history = client.get_metric_history(child.info.run_id, "loss.validation")
        assert [m.step for m in history] == list(range(len(history))) and len(history) >= 1
        want = {f"validation.{t}.{m}" for t in TARGETS for m in ("mse", "dtw", "peak_error_median")}
        assert want <= set(child.data.metrics)
    logged = mlflow.search_logged_models(
        experiment_ids=[experiment.experiment_id], output_format="list"
    )
    # one per child (refine's fine-tuned models, logged by other stage tests, are not train's)
    models = [m for m in logged if m.source_run_id in {c.info.run_id for c in children}]
    assert len(models) == 2
    loaded = mlflow.pytorch.load_model(f"models:/{models[0].model_id}")
    assert loaded(torch.zeros(1, 24, 4)).shape == (1, 24, len(TARGETS))


def test_every_model_is_a_registered_version_and_the_used_one_has_the_alias(trained):
    _, uri, data = trained
    import mlflow

    client = mlflow.MlflowClient(tracking_uri=uri)
    alias, use = data["train"]["alias"], data["train"]["use"]
    for loss in data["train"]["losses"]:
        name = f"ftfof-mst_m3f-{loss}"
        versions = client.search_model_versions(f"name = '{name}'")
        # refine's fine-tuned models are versions too (other stage tests share the store)
        (run,) = [
            r
            for r in (client.get_run(v.run_id) for v in versions)
            if r.data.tags["mlflow.source.name"] == "train"
        ]
        assert run.data.params["loss"] == loss and run.data.params["targets"] == ",".join(TARGETS)
    champion = client.get_model_version_by_alias(f"ftfof-mst_m3f-{use}", alias)
    assert client.get_run(champion.run_id).data.params["loss"] == use


def test_every_train_run_records_the_dataset_it_trained_on(trained):
    tmp, uri, _ = trained
    import hashlib

    import mlflow

    client = mlflow.MlflowClient(tracking_uri=uri)
    experiment = client.get_experiment_by_name("ftfof-mst_m3f")
    md5 = hashlib.md5((tmp / "ds" / "samples.parquet").read_bytes()).hexdigest()
    runs = client.search_runs([experiment.experiment_id], "tags.`dvc.stage` = 'train'")
    assert len(runs) == 3  # the parent and its two children (other stages share the store)
    for run in runs:
        (entry,) = run.inputs.dataset_inputs
        assert entry.dataset.digest == md5
        assert "data/dataset/samples.parquet" in entry.dataset.source
        assert {t.key: t.value for t in entry.tags}["mlflow.data.context"] == "training"


def child_seconds(tmp, child) -> float:
    """The training seconds of ``child``'s model, as train's metrics file records them."""
    return json.loads((tmp / "models.json").read_text())[child.data.tags["loss"]]["seconds"]
