"""A real `mlflow ui` on 127.0.0.1 serves the training runs over its REST API (slow)."""

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest
from PIL import Image

pytestmark = pytest.mark.slow


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _call(url: str, body: dict | None = None) -> dict:
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(url, data=data, headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=30) as resp:
        return json.loads(resp.read())


def _registry_is_served(base: str, tmp_path: Path) -> None:
    """The registered models with their versions and the alias, and the model page rendered."""
    models = _call(f"{base}/api/2.0/mlflow/registered-models/search?max_results=100")
    names = {m["name"] for m in models["registered_models"]}
    assert {f"ftfof-mst_m3f-{k}" for k in ("dilate", "mse")} <= names
    champion = _call(  # params.yaml: train.use = mse
        f"{base}/api/2.0/mlflow/registered-models/alias?name=ftfof-mst_m3f-mse&alias=champion"
    )["model_version"]
    run = _call(f"{base}/api/2.0/mlflow/runs/get?run_id={champion['run_id']}")["run"]
    assert {p["key"]: p["value"] for p in run["data"]["params"]}["loss"] == "mse"
    (entry,) = run["inputs"]["dataset_inputs"]
    assert entry["dataset"]["source"].endswith('"data/dataset/samples.parquet"}')
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    shot = tmp_path / "model_page.png"
    subprocess.run(
        [
            chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
            "--no-first-run", "--disable-background-networking", "--disable-component-update",
            "--disable-sync", f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1280,900",
            "--virtual-time-budget=15000", f"--screenshot={shot}",
            f"{base}/#/models/ftfof-mst_m3f-mse",
        ],
        check=True, capture_output=True, timeout=180,
    )  # fmt: skip
    image = Image.open(shot).convert("RGB")
    assert image.size == (1280, 900)
    # the model page, not a blank one or a spinner: text, the versions table and the alias tag
    assert len(image.getcolors(maxcolors=1 << 20) or []) > 50
    keep = os.environ.get("FTFOF_KEEP_SCREENSHOT")
    if keep:
        shutil.copy(shot, keep)


def test_mlflow_ui_serves_the_runs_and_a_metric_history(trained, tmp_path):
    tmp, uri, _ = trained
    port = _port()
    mlflow = str(Path(sys.executable).parent / "mlflow")
    env = {**os.environ, "MLFLOW_DISABLE_TELEMETRY": "true"}
    proc = subprocess.Popen(
        [
            mlflow,
            "ui",
            "--backend-store-uri",
            uri,
            "--host",
            "127.0.0.1",
            "--port",
            str(port),
            "--workers",
            "1",
        ],
        cwd=tmp,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 180
        while True:
            try:
                with urllib.request.urlopen(f"{base}/health", timeout=5) as resp:
                    if resp.status == 200:
                        break
            except OSError:
                pass
            assert proc.poll() is None, "mlflow ui exited"
            assert time.monotonic() < deadline, "mlflow ui did not come up"
            time.sleep(1)
        experiment = _call(
            f"{base}/api/2.0/mlflow/experiments/get-by-name?experiment_name=ftfof-mst_m3f"
        )
        exp_id = experiment["experiment"]["experiment_id"]
        runs = _call(f"{base}/api/2.0/mlflow/runs/search", {"experiment_ids": [exp_id]})["runs"]
        names = sorted(r["info"]["run_name"] for r in runs)  # other stage tests share the store
        others = ("optimize", "refine", "polish", "evaluate")
        assert [n for n in names if n.partition("-")[0] not in others] == ["dilate", "mse", "train"]
        child = next(r for r in runs if r["info"]["run_name"] == "dilate")
        history = _call(
            f"{base}/api/2.0/mlflow/metrics/get-history?run_id={child['info']['run_id']}&metric_key=loss.validation"
        )["metrics"]
        assert [m["step"] for m in history] == list(range(len(history))) and history
        with urllib.request.urlopen(f"{base}/", timeout=30) as resp:
            assert resp.status == 200  # the UI page itself
        _registry_is_served(base, tmp_path)
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
