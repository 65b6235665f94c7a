"""Stage `train` gives the same model files on any x86-64 machine: the tiny models' digests are
those committed from the CI machine, and MKL's code path (which picks its kernels by the CPU's
vendor) has no say in them."""

import json
import os
import subprocess
import sys

import pytest

from ftfof.digests import file_sha256
from ftfof.pipeline import machine
from tests.conftest import ROOT

COMMITTED = ROOT / "tests" / "data" / "model_digests.json"
RECORD = "FTFOF_RECORD_MODEL_DIGESTS"


def _file_digests(directory) -> dict[str, str]:
    """SHA-256 of every file of a model directory: what DVC's hash of it is made of."""
    return {p.name: file_sha256(p) for p in sorted(directory.iterdir()) if p.is_file()}


@pytest.mark.integration
def test_the_tiny_models_are_the_committed_bits_on_this_machine(trained):
    """Would have caught the AMD machine's other weights: the digests come from the machine that
    produced the committed dvc.lock, and a machine that trains other bits fails by name."""
    tmp, _, _ = trained
    ours = {"machine": machine.describe(), "files": _file_digests(tmp / "models")}
    if os.environ.get(RECORD) == "1":  # a deliberate change of the models, on the CI machine
        COMMITTED.write_text(json.dumps(ours, indent=1) + "\n")
    committed = json.loads(COMMITTED.read_text())
    assert ours["files"] == committed["files"], (
        f"this machine, {machine.label(ours['machine'])}, trained other tiny models than "
        f"{machine.label(committed['machine'])}, whose digests {COMMITTED.relative_to(ROOT)} "
        f"holds (after a deliberate change of the models, record them again on the CI machine "
        f"with {RECORD}=1).\nthis machine: {json.dumps(ours, indent=1)}\n"
        f"committed: {json.dumps(committed, indent=1)}"
    )


_MKL_PRODUCT = """
import hashlib, os, sys
os.environ["MKL_CBWR"] = sys.argv[1]
import torch
torch.manual_seed(0)
a, b = torch.randn(64, 1000), torch.randn(1000, 64)
print(hashlib.sha256((a @ b).numpy().tobytes()).hexdigest())
"""
_TRAIN_ON_BRANCH = """
import os, sys
import stages  # pins the numerical paths, MKL's branch included ...
os.environ["MKL_CBWR"] = sys.argv[1]  # ... which this process then overrides before MKL loads
from stages.cli import main
sys.argv = ["ftfof", "train", *sys.argv[2:]]
main()
"""


def _python(code: str, *args, env=None) -> str:
    result = subprocess.run(
        [sys.executable, "-c", code, *map(str, args)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stderr
    return result.stdout


@pytest.mark.slow
def test_training_does_not_depend_on_mkls_code_path(trained, tmp_path):
    """MKL's COMPATIBLE (SSE2) and AVX2 branches multiply to other bits (checked here, so the
    setting does reach MKL), yet train the same model files: MKL is off the training path."""
    tmp, _, _ = trained
    products, digests = {}, {}
    for branch in ("COMPATIBLE", "AVX2"):
        products[branch] = _python(_MKL_PRODUCT, branch).split()[0]
        out = tmp_path / branch
        args = ["-p", tmp / "models.yaml", "--dataset", tmp / "ds", "--out", out]
        args += ["--metrics", out.with_suffix(".json")]
        args += ["--loss-plot", out.with_suffix(".l.png"), "--pred-plot", out.with_suffix(".p.png")]
        env = {**os.environ, "MLFLOW_TRACKING_URI": f"sqlite:///{tmp_path / branch}.db"}
        _python(_TRAIN_ON_BRANCH, branch, *args, env=env)
        digests[branch] = _file_digests(out)
    assert products["COMPATIBLE"] != products["AVX2"]
    assert digests["COMPATIBLE"] == digests["AVX2"] == _file_digests(tmp / "models")
