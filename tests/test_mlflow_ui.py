"""A real `mlflow ui` on 127.0.0.1 serves the training runs over its REST API, and opens the
experiment on its runs in headless Chromium (slow)."""

import json
import os
import re
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


def _chromium(url: str, tmp_path: Path, name: str, *output: str) -> str:
    """``url`` in headless Chromium at 1280 x 900 (``output``: --dump-dom or --screenshot=...);
    its stdout."""
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    return subprocess.run(
        [
            chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
            "--no-first-run", "--disable-background-networking", "--disable-component-update",
            "--disable-sync", f"--user-data-dir={tmp_path / name}", "--window-size=1280,900",
            "--virtual-time-budget=15000", *output, url,
        ],
        check=True, capture_output=True, text=True, timeout=180,
    ).stdout  # fmt: skip


def _keep(shot: Path) -> None:
    """FTFOF_KEEP_SCREENSHOT=<dir> keeps the screenshots there, to look at."""
    keep = os.environ.get("FTFOF_KEEP_SCREENSHOT")
    if keep:
        Path(keep).mkdir(parents=True, exist_ok=True)
        shutil.copy(shot, Path(keep) / shot.name)


def _experiment_opens_on_its_runs(base: str, experiment: dict, tmp_path: Path) -> None:
    """The experiment declares itself a model-training one, and the page the README sends a
    user to lists the runs, not MLflow's GenAI overview (traces, token usage). MLflow 3.17's UI
    reads the kind from its GenAI / Model training switch, not the tag: the README's address
    sets the switch."""
    tags = {t["key"]: t["value"] for t in experiment["tags"]}
    assert tags["mlflow.experimentKind"] == "custom_model_development"
    url = f"{base}/#/experiments/{experiment['experiment_id']}?workflowType=machine_learning"
    dom = _chromium(url, tmp_path, "runs-dom", "--dump-dom")
    title = re.search(r"<title>([^<]*)</title>", dom).group(1)
    assert title == f"Runs - Experiment {experiment['experiment_id']} - MLflow"
    tags_out = re.sub(r"<[^>]+>", " ", re.sub(r"<(script|style)\b.*?</\1>", "", dom, flags=re.S))
    text = f" {' '.join(tags_out.split())} "
    # the runs table (the loss runs nest under train), not the overview's token charts
    assert " Run Name " in text and " train " in text and re.search(r" \d+ matching runs ", text)
    assert "Token Usage" not in text
    shot = tmp_path / "experiment_runs.png"
    _chromium(url, tmp_path, "runs-shot", f"--screenshot={shot}")
    image = Image.open(shot).convert("RGB")
    assert image.size == (1280, 900) and len(image.getcolors(maxcolors=1 << 20) or []) > 50
    _keep(shot)


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
    shot = tmp_path / "model_page.png"
    _chromium(f"{base}/#/models/ftfof-mst_m3f-mse", tmp_path, "profile", f"--screenshot={shot}")
    image = Image.open(shot).convert("RGB")
    assert image.size == (1280, 900)
    # the model page, not a blank one or a spinner: text, the versions table and the alias tag
    assert len(image.getcolors(maxcolors=1 << 20) or []) > 50
    _keep(shot)


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
        _experiment_opens_on_its_runs(base, experiment["experiment"], tmp_path)
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
