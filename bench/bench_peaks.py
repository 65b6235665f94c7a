"""What the peak GPs add to one population's surrogate evaluation (the optimiser's hot path).

Baseline: the GRU pass alone (the surrogate without its peak models), in the same process, on
the same population; then the same with the peak models, and the GP prediction alone. Also the
refit a refine round does (one Cholesky solve per GP on the grown data).

Run: python bench/bench_peaks.py [population] [models]   (default 200, the paper's, and
data/models; data/refine/models has the near-front GPs). Needs the trained models
(`dvc repro train`).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import best_of, row
from ftfof.pipeline import catalog
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.params_file import load_params
from ftfof.surrogate.peaks import NearFront
from ftfof.surrogate.store import load_surrogate


def main(population: int, models: str) -> None:
    root = Path(__file__).resolve().parents[1]
    params = load_params(root / "params.yaml")
    policy = context_of(params).policy
    surrogate = load_surrogate(root / models)
    if not surrogate.peaks:
        raise SystemExit(f"the models in {models} have no peak models (train.peaks)")
    gru_only = replace(surrogate, peaks={})
    rng = np.random.default_rng(0)
    free = policy.lower + rng.random((population, policy.n_free)) * (policy.upper - policy.lower)
    X = policy.expand(free)
    on_base = policy.sample(X, surrogate.time_base(policy.timing.T3))
    pos, vel = on_base.position, on_base.velocity
    base = best_of(lambda: gru_only.predict(pos, vel), repeats=20)
    both = best_of(lambda: surrogate.predict(pos, vel, decisions=X), repeats=20)
    print(f"population {population}; peak models {sorted(surrogate.peaks)}")
    print(row("GRU pass (baseline)", base, base))
    print(row("GRU pass + peak GPs", both, base))
    gru_peaks = gru_only.predict(pos, vel)
    for name, model in surrogate.peaks.items():
        series_peak = gru_peaks[name].max(axis=-1)  # a near-front model without a broad GP
        near = isinstance(model, NearFront)
        rows = (model.local if near else model).train_inputs.shape[0]
        print(
            row(
                f"{name} {'near-front GP' if near else 'GP'} alone ({rows} rows)",
                best_of(lambda m=model, g=series_peak: m(X, g), repeats=20),
                base,
            )
        )
    for name, model in surrogate.peaks.items():
        model = model.broad if isinstance(model, NearFront) else model
        if model is None:  # a local GP alone: fitted anew each round, never refitted
            continue
        Xt = model.train_inputs * model.input_scale + model.input_mean
        grown = np.vstack([Xt, Xt[:150] + 1e-4])  # a refine run's 150 new rows
        peaks = model(grown)
        seconds = best_of(lambda m=model, g=grown, p=peaks: m.refit(g, p), repeats=3)
        print(row(f"{name} refit on {len(grown)} rows", seconds, base))


if __name__ == "__main__":
    main(
        int(sys.argv[1]) if len(sys.argv) > 1 else 200,
        sys.argv[2] if len(sys.argv) > 2 else catalog.path("models"),
    )
