"""The model directory: what the writer puts there the reader loads, byte for byte."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import torch

from ftfof.config import Train
from ftfof.data.dataset import TARGETS, Normalization
from ftfof.surrogate.model import ForceGRU, ModelConfig
from ftfof.surrogate.store import load_surrogate, write_models


def test_written_models_load_as_the_surrogate_they_were(tmp_path: Path, params):
    cfg: Train = params.train.model_copy(update={"hidden": 4, "layers": 1, "losses": ["dilate"]})
    torch.manual_seed(0)
    k = len(TARGETS)
    model = ForceGRU(ModelConfig(hidden=4, layers=1, outputs=k))
    state = {name: v.numpy() for name, v in model.state_dict().items()}
    results = [{"kind": "dilate", "state": state}]
    norm = Normalization([0.0] * 4, [1.0] * 4, [float(i + 1) for i in range(k)])
    trained = TARGETS[:-1]  # no film channel in this dataset
    data = SimpleNamespace(
        normalization=norm, seq_len=12, hold=0.1, metadata_digest="abc", trained=trained
    )
    out = tmp_path / "models"
    write_models(out, results, data, cfg)
    assert sorted(p.name for p in out.iterdir()) == [
        "config.json",
        "normalization.json",
        "surrogate_dilate.pt",
    ]
    config = json.loads((out / "config.json").read_text())
    assert config["use"] == cfg.use and config["dataset"] == "abc" and config["seq_len"] == 12
    assert config["trained"] == list(trained) and config["model"]["outputs"] == k
    surrogate = load_surrogate(out, "dilate")
    x = np.random.default_rng(0).normal(size=(3, 12, 4)).astype(np.float32)
    with torch.no_grad():
        want = model(torch.from_numpy(x)).numpy()
    np.testing.assert_allclose(surrogate.model(x), want, rtol=1e-4, atol=1e-5)
    series = surrogate.predict(x[..., :2], x[..., 2:])  # features with mean 0, scale 1
    assert set(series) == set(trained)
    np.testing.assert_allclose(series["Fp"], want[..., 2] * 3.0, rtol=1e-4, atol=1e-5)
    assert (surrogate.seq_len, surrogate.hold) == (12, 0.1)
