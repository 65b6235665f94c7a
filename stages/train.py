"""Stage `train`: GRU surrogates (Fd, Fp) with DILATE and MSE, tracked in MLflow -> data/models/."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Annotated

import typer

from ftfof.pipeline.registry import TARGETS
from stages.common import ParamsOption, atomic_dir, atomic_path, console, stage, write_json

DATASET = Path("data/dataset")
OUT = Path("data/models")
METRICS = Path("reports/train_metrics.json")
LOSS_PLOT = Path("reports/train_loss.png")
PRED_PLOT = Path("reports/train_predictions.png")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    dataset_dir: Annotated[Path, typer.Option("--dataset", help="Dataset directory.")] = DATASET,
    out: Annotated[Path, typer.Option(help="Model directory to write.")] = OUT,
    metrics: Annotated[Path, typer.Option(help="Metrics JSON.")] = METRICS,
    loss_plot: Annotated[Path, typer.Option(help="Validation loss curves (Fig. 8).")] = LOSS_PLOT,
    pred_plot: Annotated[Path, typer.Option(help="Predicted vs measured (Fig. 9).")] = PRED_PLOT,
) -> None:
    """Train trajectory -> force GRUs with DILATE (and MSE for comparison); log to MLflow."""

    from ftfof.report.figures import loss_figure, prediction_figure
    from stages.surrogates import read_dataset

    params = load(params_path)
    cfg = params.train
    data = read_dataset(dataset_dir)
    jobs = [
        {"target": t, "index": i, "kind": k, "seed": params.base.seed + cfg.seed_offset + 10 * i}
        for i, t in enumerate(TARGETS)
        for k in cfg.losses
    ]
    started = time.perf_counter()
    results = run_jobs(jobs, data, cfg)
    wall = time.perf_counter() - started
    summary = {
        f"{r['target']}_{r['kind']}": {
            **r["metrics"],
            "epochs": len(r["history"]["train"]),
            "best_epoch": r["history"]["best_epoch"],
            "seconds": round(r["seconds"], 2),
        }
        for r in results
    }
    summary["wall_seconds"] = round(wall, 2)
    loss_fig = loss_figure(results)
    pred_fig = prediction_figure(results, data, params.base.seed)
    _write_models(out, results, data, cfg)
    write_json(metrics, summary)
    for fig, path in ((loss_fig, loss_plot), (pred_fig, pred_plot)):
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format="png", dpi=100)
    _track(params, results, data, summary, (loss_plot, pred_plot), out, dataset_dir)
    for r in results:
        m = r["metrics"]
        console.print(
            f"{r['target']} {r['kind']:6s}: peak error median {m['peak_error_median']:.3f} N, "
            f"p90 {m['peak_error_p90']:.3f} N, DTW {m['dtw']:.3f}, MSE {m['mse']:.4f} "
            f"({len(r['history']['train'])} epochs, {r['seconds']:.0f} s)"
        )
    console.print(f"trained {len(results)} models in {wall:.0f} s -> {out}")


def load(params_path: Path):
    from stages.params import load_params

    return load_params(params_path)


def run_jobs(jobs: list[dict], data, cfg) -> list[dict]:
    """Train every job, side by side in processes when asked (one torch thread pool each)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    cores = os.cpu_count() or 1
    workers = min(len(jobs), cores) if cfg.parallel else 1
    threads = cfg.threads or max(1, cores // workers)
    if workers == 1:
        return [_train_one(job, data, cfg, threads) for job in jobs]
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
        futures = [pool.submit(_train_one, job, data, cfg, threads) for job in jobs]
        return [f.result() for f in futures]


def _train_one(job: dict, data, cfg, threads: int) -> dict:
    import numba
    import torch

    from ftfof.surrogate.train import predict, train_model, validation_metrics

    torch.set_num_threads(threads)
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    i = job["index"]
    x_tr, y_tr = data.inputs("train"), data.target("train", i)
    x_va, y_va = data.inputs("validation"), data.target("validation", i)
    trained = train_model(x_tr, y_tr, x_va, y_va, job["kind"], cfg, job["seed"])
    scale = data.target_scale[i]
    pred = predict(trained.model, x_va)[..., 0] * scale
    truth = y_va[..., 0] * scale
    return {
        **job,
        "state": {k: v.numpy() for k, v in trained.model.state_dict().items()},
        "history": {
            "train": trained.history.train,
            "validation": trained.history.validation,
            "best_epoch": trained.history.best_epoch,
        },
        "metrics": validation_metrics(pred, truth, data.dt),
        "seconds": trained.seconds,
        "val_pred": pred,
        "val_truth": truth,
    }


def _write_models(out: Path, results: list[dict], data, cfg) -> None:
    """State dicts (torch.load(weights_only=True)), normalisation and config, all or nothing."""
    import torch

    from ftfof.pipeline.registry import weights_file

    with atomic_dir(out) as tmp:
        for r in results:
            state = {k: torch.from_numpy(v) for k, v in r["state"].items()}
            torch.save(state, tmp / weights_file(r["target"], r["kind"]))
        (tmp / "normalization.json").write_text(data.normalization.to_json() + "\n")
        config = {
            "model": {
                "inputs": 4,
                "hidden": cfg.hidden,
                "layers": cfg.layers,
                "dropout": cfg.dropout,
            },
            "targets": list(TARGETS),
            "losses": list(cfg.losses),
            "use": cfg.use,
            "seq_len": data.seq_len,
            "hold": data.hold,
            "dataset": data.metadata_digest,
        }
        (tmp / "config.json").write_text(json.dumps(config, indent=2, sort_keys=True) + "\n")


def _track(
    params,
    results: list[dict],
    data,
    summary: dict,
    figures: tuple[Path, ...],
    out: Path,
    dataset_dir: Path,
) -> None:
    """One parent run per invocation, a child per model and loss; every model is registered as a
    version of ``ftfof-<robot>-<target>-<loss>``, and the ``use`` pair gets the alias."""
    import numpy as np
    import torch

    from ftfof.pipeline.registry import model_name, weights_file
    from ftfof.surrogate.model import ForceGRU, ModelConfig
    from stages import tracking
    from stages.surrogates import models_digest

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
    settings = {
        "train": cfg.model_dump(),
        "dataset": params.dataset.model_dump(),
        "robot": params.robot,
        "surface": params.surface,
        "dataset_digest": data.metadata_digest,
    }
    flat = tracking.flatten(settings)
    with mlflow.start_run(run_name="train", tags=parent_tags):
        mlflow.log_input(dataset_input, context="training")
        mlflow.log_params(flat)
        mlflow.log_metric("wall_seconds", summary["wall_seconds"])
        for path in figures:
            mlflow.log_artifact(str(path), artifact_path="figures")
        for r in results:
            with mlflow.start_run(
                run_name=f"{r['target']}-{r['kind']}",
                nested=True,
                tags={**tags, "target": r["target"], "loss": r["kind"]},
            ):
                mlflow.log_input(dataset_input, context="training")
                mlflow.log_params(
                    {**flat, "target": r["target"], "loss": r["kind"], "seed": r["seed"]}
                )
                client = mlflow.MlflowClient()
                run_id = mlflow.active_run().info.run_id
                from mlflow.entities import Metric

                stamp = int(time.time() * 1000)
                batch = [
                    Metric(f"{split}_loss", v, stamp, e)
                    for split in ("train", "validation")
                    for e, v in enumerate(r["history"][split])
                ]
                for start in range(0, len(batch), 900):
                    client.log_batch(run_id, metrics=batch[start : start + 900])
                mlflow.log_metrics({f"val_{k}": v for k, v in r["metrics"].items()})
                mlflow.log_metric("best_epoch", r["history"]["best_epoch"])
                model = ForceGRU(
                    ModelConfig(hidden=cfg.hidden, layers=cfg.layers, dropout=cfg.dropout)
                )
                model.load_state_dict({k: torch.from_numpy(v) for k, v in r["state"].items()})
                model.eval()
                with torch.no_grad():
                    output = model(torch.from_numpy(example)).numpy()
                name = model_name(params.robot, r["target"], r["kind"])
                info = mlflow.pytorch.log_model(
                    model,
                    name="model",
                    signature=infer_signature(example, output),
                    input_example=example,
                    pip_requirements=requirements,
                    serialization_format="pickle",
                    registered_model_name=name,
                    extra_files=[str(out / weights_file(r["target"], r["kind"]))],
                )
                if r["kind"] == cfg.use:
                    client.set_registered_model_alias(
                        name, cfg.alias, str(info.registered_model_version)
                    )
