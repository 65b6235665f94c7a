"""Stage `train`: outputs loadable with weights_only, metrics and figures, MLflow runs."""

import json

import torch

from stages.surrogates import load_surrogate


def test_models_load_with_weights_only(trained):
    tmp, _, _ = trained
    for target in ("Fd", "Fp"):
        for loss in ("dilate", "mse"):
            state = torch.load(tmp / "models" / f"{target}_{loss}.pt", weights_only=True)
            assert "gru.weight_ih_l0" in state and "head.weight" in state
    config = json.loads((tmp / "models" / "config.json").read_text())
    assert config["use"] == "dilate" and config["seq_len"] == 24
    surrogate = load_surrogate(tmp / "models")
    assert surrogate.seq_len == 24


def test_metrics_and_figures(trained):
    tmp, _, _ = trained
    metrics = json.loads((tmp / "m.json").read_text())
    for name in ("Fd_dilate", "Fd_mse", "Fp_dilate", "Fp_mse"):
        assert {
            "mse",
            "dtw",
            "peak_error_median",
            "peak_error_p90",
            "peak_time_error_median",
        } <= set(metrics[name])
    for png in ("loss.png", "pred.png"):
        assert (tmp / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_mlflow_holds_the_parent_and_child_runs_with_params_metrics_models_and_tags(trained):
    _, uri, data = trained
    import mlflow

    client = mlflow.MlflowClient(tracking_uri=uri)
    experiment = client.get_experiment_by_name("ftfof-mst_m3f")
    runs = client.search_runs([experiment.experiment_id])
    parent = [r for r in runs if r.info.run_name == "train"]
    children = [r for r in runs if r.data.tags.get("mlflow.parentRunId")]
    assert len(parent) == 1 and len(children) == 4
    p = parent[0]
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
    figures = {a.path for a in client.list_artifacts(p.info.run_id, "figures")}
    assert figures == {"figures/loss.png", "figures/pred.png"}
    for child in children:
        assert child.data.params["train.epochs"] == str(data["train"]["epochs"])
        history = client.get_metric_history(child.info.run_id, "validation_loss")
        assert [m.step for m in history] == list(range(len(history))) and len(history) >= 1
        assert {"val_mse", "val_dtw", "val_peak_error_median", "val_peak_time_error_median"} <= set(
            child.data.metrics
        )
    models = mlflow.search_logged_models(
        experiment_ids=[experiment.experiment_id], output_format="list"
    )
    assert len(models) == 4
    loaded = mlflow.pytorch.load_model(f"models:/{models[0].model_id}")
    assert loaded(torch.zeros(1, 24, 4)).shape == (1, 24, 1)
