"""The model directory: what the writer puts there the reader loads, byte for byte."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import torch

from ftfof.config import Train
from ftfof.data.dataset import Normalization
from ftfof.surrogate.model import ForceGRU, ModelConfig
from ftfof.surrogate.store import load_surrogate, write_models


def test_written_models_load_as_the_surrogate_they_were(tmp_path: Path, params):
    cfg: Train = params.train.model_copy(update={"hidden": 4, "layers": 1, "losses": ["dilate"]})
    torch.manual_seed(0)
    results = []
    for target in ("Fd", "Fp"):
        model = ForceGRU(ModelConfig(hidden=4, layers=1))
        state = {k: v.numpy() for k, v in model.state_dict().items()}
        results.append({"target": target, "kind": "dilate", "state": state})
    norm = Normalization([0.0] * 4, [1.0] * 4, [1.0, 1.0])
    data = SimpleNamespace(normalization=norm, seq_len=12, hold=0.1, metadata_digest="abc")
    out = tmp_path / "models"
    write_models(out, results, data, cfg)
    assert sorted(p.name for p in out.iterdir()) == [
        "Fd_dilate.pt",
        "Fp_dilate.pt",
        "config.json",
        "normalization.json",
    ]
    config = json.loads((out / "config.json").read_text())
    assert config["use"] == cfg.use and config["dataset"] == "abc" and config["seq_len"] == 12
    surrogate = load_surrogate(out, "dilate")
    x = np.random.default_rng(0).normal(size=(3, 12, 4)).astype(np.float32)
    with torch.no_grad():
        expected = ForceGRU(ModelConfig(hidden=4, layers=1))
        expected.load_state_dict({k: torch.from_numpy(v) for k, v in results[0]["state"].items()})
        want = expected(torch.from_numpy(x)).numpy()[..., 0]
    np.testing.assert_allclose(surrogate.detachment(x), want, rtol=1e-4, atol=1e-5)
    assert (surrogate.seq_len, surrogate.hold) == (12, 0.1)
