"""The model directory: what the writer puts there the reader loads, byte for byte."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import torch

from ftfof.config import Train
from ftfof.data.dataset import TARGETS, Normalization
from ftfof.errors import DataError
from ftfof.surrogate.model import ForceGRU, ModelConfig
from ftfof.surrogate.peaks import fit_peak_model
from ftfof.surrogate.predict import with_peak
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
    rng = np.random.default_rng(1)
    decisions = rng.uniform(size=(20, 12))
    peak = fit_peak_model("Fp", decisions, 4.0 + decisions[:, 11])
    out = tmp_path / "models"
    write_models(out, results, data, cfg, {"Fp": peak})
    assert sorted(p.name for p in out.iterdir()) == [
        "config.json",
        "normalization.json",
        "peaks.json",
        "surrogate_dilate.pt",
    ]
    config = json.loads((out / "config.json").read_text())
    assert config["use"] == cfg.use and config["dataset"] == "abc" and config["seq_len"] == 12
    assert config["trained"] == list(trained) and config["model"]["outputs"] == k
    assert config["peaks"] == ["Fp"]
    surrogate = load_surrogate(out, "dilate")
    x = np.random.default_rng(0).normal(size=(3, 12, 4)).astype(np.float32)
    with torch.no_grad():
        want = model(torch.from_numpy(x)).numpy()
    np.testing.assert_allclose(surrogate.model(x), want, rtol=1e-4, atol=1e-5)
    with pytest.raises(ValueError, match=r"peaks of \['Fp'\] come from the control values"):
        surrogate.predict(x[..., :2], x[..., 2:])
    with pytest.raises(ValueError, match="1 rows of control values for 3 trajectories"):
        surrogate.predict(x[..., :2], x[..., 2:], decisions=decisions[:1])
    # features with mean 0, scale 1; Fp takes the GRU's shape and the GP's peak
    series = surrogate.predict(x[..., :2], x[..., 2:], decisions=decisions[:3])
    assert set(series) == set(trained)
    np.testing.assert_allclose(series["Fd"], want[..., 1] * 2.0, rtol=1e-4, atol=1e-5)
    want_fp = with_peak(want[..., 2] * 3.0, peak(decisions[:3]))
    np.testing.assert_allclose(series["Fp"], want_fp, rtol=1e-4, atol=1e-5)
    np.testing.assert_allclose(series["Fp"].max(-1), peak(decisions[:3]), rtol=1e-12)
    assert (surrogate.seq_len, surrogate.hold) == (12, 0.1)


def test_a_model_directory_missing_its_peak_models_is_named(tmp_path: Path, params):
    cfg: Train = params.train.model_copy(update={"hidden": 4, "layers": 1, "losses": ["dilate"]})
    model = ForceGRU(ModelConfig(hidden=4, layers=1, outputs=len(TARGETS)))
    state = {name: v.numpy() for name, v in model.state_dict().items()}
    norm = Normalization([0.0] * 4, [1.0] * 4, [1.0] * len(TARGETS))
    data = SimpleNamespace(
        normalization=norm, seq_len=12, hold=0.1, metadata_digest="abc", trained=TARGETS
    )
    decisions = np.random.default_rng(2).uniform(size=(10, 12))
    peak = fit_peak_model("jitter", decisions, decisions[:, 0])
    out = tmp_path / "models"
    write_models(out, [{"kind": "dilate", "state": state}], data, cfg, {"jitter": peak})
    (out / "peaks.json").unlink()
    with pytest.raises(DataError, match=r"peaks.json: missing: config.json lists .*jitter"):
        load_surrogate(out, "dilate")
