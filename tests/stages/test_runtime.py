"""Process-wide numerics: the pinned MKL and numba code paths reach every pipeline process."""

import os
import subprocess
import sys

import pytest

from stages import runtime
from tests.conftest import ROOT


def test_pinning_overrides_the_callers_choice_on_x86_64(monkeypatch):
    monkeypatch.setattr(runtime.platform, "machine", lambda: "x86_64")
    env = {"MKL_CBWR": "AVX512", "NUMBA_CPU_NAME": "skylake-avx512"}
    assert runtime.pin_numerics(env) == runtime.PINNED_X86_64
    assert env == {
        "MKL_CBWR": "COMPATIBLE",
        "ATEN_CPU_CAPABILITY": "avx2",
        "NUMBA_CPU_NAME": "haswell",
        "NUMBA_CPU_FEATURES": "",
        "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR",
        "OPENBLAS_CORETYPE": "Haswell",
    }


def test_the_test_process_itself_runs_numpy_on_the_pinned_kernels():
    """The root conftest pins before numpy loads: the local pool forks this process, Dask's
    workers start fresh, and both must compute alike."""
    from numpy._core._multiarray_umath import __cpu_features__ as numpy_uses

    if runtime.platform.machine().lower() in {"x86_64", "amd64"}:
        assert os.environ["NPY_DISABLE_CPU_FEATURES"] == "X86_V4 AVX512_ICL AVX512_SPR"
        assert not any(numpy_uses.get(f, False) for f in ("X86_V4", "AVX512_ICL", "AVX512_SPR"))


def test_other_architectures_keep_their_native_paths(monkeypatch):
    monkeypatch.setattr(runtime.platform, "machine", lambda: "aarch64")
    env = {"MKL_CBWR": "AUTO"}
    assert runtime.pin_numerics(env) == {} and env == {"MKL_CBWR": "AUTO"}


@pytest.mark.integration  # starts a stage process
def test_a_stage_process_compiles_for_the_pinned_target_whatever_the_host_says():
    env = {**os.environ, "MKL_CBWR": "AVX512", "NUMBA_CPU_NAME": "skylake-avx512"}
    env["ATEN_CPU_CAPABILITY"] = "avx512"
    code = (
        "import stages.cli, os; from numba.core import config; "
        "from numpy._core._multiarray_umath import __cpu_features__ as numpy_uses; "
        "import torch; "
        "print(os.environ['MKL_CBWR'], config.CPU_NAME, repr(config.CPU_FEATURES), "
        "any(numpy_uses.get(f, False) for f in ('X86_V4', 'AVX512_ICL', 'AVX512_SPR')), "
        "torch.backends.cpu.get_cpu_capability())"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, check=True
    )
    if runtime.platform.machine().lower() in {"x86_64", "amd64"}:
        # numpy: no AVX-512; torch's ATen: its AVX2 kernels
        assert out.stdout.split() == ["COMPATIBLE", "haswell", "''", "False", "AVX2"]
