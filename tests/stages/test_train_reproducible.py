"""Stage `train` gives bit-identical weights and peak GPs across CPU instruction sets
(end-to-end, minutes)."""

import pytest
import torch

pytestmark = pytest.mark.slow


def _state_digest(directory) -> dict[str, str]:
    import hashlib

    out = {}
    for path in sorted(directory.glob("*.pt")):
        state = torch.load(path, weights_only=True)
        h = hashlib.sha256()
        for key in sorted(state):
            h.update(key.encode() + state[key].numpy().tobytes())
        out[path.name] = h.hexdigest()
    peaks = directory / "peaks.json"  # the GPs' fit: BLAS and scipy's optimiser, pinned alike
    out["peaks.json"] = hashlib.sha256(peaks.read_bytes()).hexdigest()
    return out


def test_training_gives_identical_weights_on_avx2_and_avx512_machines(trained, tmp_path):
    """The same stage under an AVX2-only machine's environment and a native (AVX-512) one."""
    import os
    import subprocess
    import sys

    from tests.conftest import ROOT

    tmp, _, data = trained
    machines = {
        "avx2": {"MKL_CBWR": "AVX2", "ATEN_CPU_CAPABILITY": "avx2"},
        "native": {},
    }
    pinned = ("MKL_CBWR", "ATEN_CPU_CAPABILITY", "NUMBA_CPU_NAME", "NUMBA_CPU_FEATURES")
    digests = {}
    for name, extra in machines.items():
        env = {k: v for k, v in os.environ.items() if k not in pinned}
        env.update(extra, MLFLOW_TRACKING_URI=f"sqlite:///{tmp_path / name}.db")
        args = ["-p", tmp / "params.yaml", "--dataset", tmp / "ds", "--out", tmp_path / name]
        args += ["--metrics", tmp_path / f"{name}.json"]
        args += [
            "--loss-plot",
            tmp_path / f"{name}_l.png",
            "--pred-plot",
            tmp_path / f"{name}_p.png",
        ]
        result = subprocess.run(
            [sys.executable, "-m", "ftfof", "train", *map(str, args)],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert result.returncode == 0, result.stderr
        digests[name] = _state_digest(tmp_path / name)
    # one multi-output model each, and the peak GPs
    assert len(digests["avx2"]) == len(data["train"]["losses"]) + 1
    assert digests["avx2"] == digests["native"]
