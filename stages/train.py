"""Stage `train`: multi-output GRU surrogates, DILATE and MSE, tracked in MLflow -> data/models/."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ftfof.pipeline.catalog import path
from stages.common import ParamsOption, console, stage

if TYPE_CHECKING:
    from ftfof.surrogate.fit import Training

DATASET = path("dataset")
OUT = path("models")
METRICS = path("train_metrics")
LOSS_PLOT = path("train_loss")
PRED_PLOT = path("train_predictions")


@stage
def command(
    params_path: Annotated[Path, ParamsOption] = Path("params.yaml"),
    dataset_dir: Annotated[Path, typer.Option("--dataset", help="Dataset directory.")] = DATASET,
    out: Annotated[Path, typer.Option(help="Model directory to write.")] = OUT,
    metrics: Annotated[Path, typer.Option(help="Metrics JSON.")] = METRICS,
    loss_plot: Annotated[Path, typer.Option(help="Validation loss curves (Fig. 8).")] = LOSS_PLOT,
    pred_plot: Annotated[Path, typer.Option(help="Predicted vs measured (Fig. 9).")] = PRED_PLOT,
) -> None:
    """Train the trajectory -> force GRU of each loss in train.losses (DILATE or MSE; the
    optimiser uses train.use) and the peak GPs of train.peaks; log and register them in MLflow."""
    from ftfof.files import save_figure
    from ftfof.pipeline.machine import describe
    from ftfof.pipeline.params_file import load_params
    from ftfof.pipeline.summaries import write_metrics
    from ftfof.pipeline.training import TrainRun, epochs_bar
    from ftfof.report.figures import loss_figure, prediction_figure
    from ftfof.seeds import seed_for
    from ftfof.surrogate.fit import train_all
    from ftfof.surrogate.store import read_dataset, write_models

    params = load_params(params_path)
    data = read_dataset(dataset_dir)
    with TrainRun(params, dataset_dir, data.metadata_digest) as tracked:  # spans the training
        with epochs_bar(params.train) as on_epoch:
            run = train_all(params.train, params.search_seed, data, on_epoch=on_epoch)
        loss_fig = loss_figure(run.results)
        pred_fig = prediction_figure(run.results, data, seed_for(params.base.seed, "plots"))
        write_models(out, run.results, data, params.train, run.peaks)
        # the machine: whose weights these are
        write_metrics("train", metrics, {**run.summary, "machine": describe()})
        save_figure(loss_fig, loss_plot)
        save_figure(pred_fig, pred_plot)
        tracked.finish(run, data, (loss_plot, pred_plot), out)
    _say(run, params.train.epochs)
    console.print(f"trained {len(run.results)} models in {run.wall:.0f} s -> {out}")


def _say(run: Training, cap: int) -> None:
    """Each model's epochs and errors, and each peak GP's, a line each."""
    for r in run.results:
        h = r["history"]
        console.print(
            f"{r['kind']}: {len(h['train'])} epochs (best {h['best_epoch']}, cap "
            f"{cap}), {r['seconds']:.0f} s"
        )
        for target, m in r["metrics"].items():
            console.print(
                f"  {target:9s} MSE {m['mse']:.4g}, DTW {m['dtw']:.4g}, "
                f"peak error median {m['peak_error_median']:.3g}, p90 {m['peak_error_p90']:.3g}"
            )
    for target, m in run.summary["peaks"].items():
        gp, gru = m["gp"], m["gru"]
        console.print(
            f"{target} peak GP: error median {gp['peak_error_median']:.3g}, p90 "
            f"{gp['peak_error_p90']:.3g}, rho {gp['spearman']:.3f} (GRU's maximum: "
            f"{gru['peak_error_median']:.3g}, {gru['peak_error_p90']:.3g}, {gru['spearman']:.3f})"
        )
    for target in run.summary["peaks_not_fitted"]:
        console.print(
            f"[yellow]{target} peak: no GP (too few training rows have control values and "
            "the target); the GRU's series maximum stands[/]"
        )
