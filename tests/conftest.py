"""Shared fixtures: params.yaml, the two robots' resolved policies, a trained tiny surrogate."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
import yaml
from typer.testing import CliRunner

from ftfof.config import Params
from ftfof.pipeline.bench import context_of
from ftfof.robot import RobotContext
from stages.cli import app

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data"

# The paper's published MST-M3F optimum (FTFOF §VI.C), metres.
PUBLISHED_M3F = np.array([2.3, 18.3, 31.4, 108.8, 123.7, 124.5, 23.6, 25.5, 29.0, 48.6, 30.5, 11.1])
PUBLISHED_M3F = PUBLISHED_M3F / 1000.0


@pytest.fixture(scope="session")
def raw_params() -> dict:
    return yaml.safe_load((ROOT / "params.yaml").read_text())


@pytest.fixture
def params_dict(raw_params: dict) -> dict:
    """A private deep copy to edit."""
    return copy.deepcopy(raw_params)


@pytest.fixture(scope="session")
def params(raw_params: dict) -> Params:
    return Params.model_validate(raw_params)


def _context(raw: dict, robot: str) -> RobotContext:
    data = copy.deepcopy(raw)
    data["robot"] = robot
    return context_of(Params.model_validate(data))


@pytest.fixture(scope="session")
def m3f(raw_params: dict) -> RobotContext:
    return _context(raw_params, "mst_m3f")


@pytest.fixture(scope="session")
def mst_q(raw_params: dict) -> RobotContext:
    return _context(raw_params, "mst_q")


def cli_args(command: str, params: Path | None = None, **options: object) -> list[str]:
    """`ftfof <command> [-p params] --an-option value ...` from keywords (underscores -> dashes)."""
    args = [command, *(["-p", str(params)] if params is not None else [])]
    for name, value in options.items():
        args += [f"--{name.replace('_', '-')}", str(value)]
    return args


def optimize_args(params: Path, models: Path, work: Path, plots: Path) -> list[str]:
    """`ftfof optimize` into ``work/optimize`` and ``work/optimize.json``; plots in ``plots``."""
    return cli_args(
        "optimize",
        params,
        models=models,
        out=work / "optimize",
        metrics=work / "optimize.json",
        convergence=plots / "optimize_convergence.csv",
        star=plots / "optimize_star.png",
        pcp=plots / "optimize_pcp.png",
    )


def refine_args(params: Path, trained: Path, optimize: Path, out: Path, figure: Path) -> list[str]:
    """`ftfof refine` on the ``trained`` dataset and models; its report is ``out`` + ``.json``."""
    return cli_args(
        "refine",
        params,
        dataset=trained / "ds",
        acquisition=trained / "acq",
        models=trained / "models",
        optimize=optimize,
        out=out,
        report=out.with_suffix(".json"),
        figure=figure,
    )


def polish_args(params: Path, refine: Path, out: Path) -> list[str]:
    """`ftfof polish` from refine's output ``refine``; its report is ``out`` + ``.json``."""
    return cli_args(
        "polish",
        params,
        optimize=refine / "optimize",
        models=refine / "models",
        out=out,
        report=out.with_suffix(".json"),
    )


def tree_bytes(directory: Path) -> dict[str, bytes]:
    """Every file under ``directory`` by relative path: two trees compare byte for byte."""
    return {
        p.relative_to(directory).as_posix(): p.read_bytes()
        for p in sorted(directory.rglob("*"))
        if p.is_file()
    }


def write_params(path: Path, data: dict) -> Path:
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def dataset_args(tmp: Path, acq: Path, imported: Path | None = None, params=None) -> list[str]:
    return cli_args(
        "dataset",
        params,
        acquisition=acq,
        imported=imported or tmp / "none",
        out=tmp / "ds",
        metrics=tmp / "ds.json",
        plot=tmp / "ds.png",
    )


@pytest.fixture(scope="session")
def trained(tmp_path_factory, raw_params):
    """A tiny dataset and the four trained models, MLflow store beside them."""
    tmp = tmp_path_factory.mktemp("train")
    data = dict(raw_params)
    data["dataset"] = {**raw_params["dataset"], "seq_len": 24}
    # as in profiles/tiny.yaml: a surrogate this small predicts no landing within 10 % of a, and
    # a retouch everywhere; trained on 30 fake records, it cannot place the body limit either
    # (with it, every row of the tiny front was refused on the 2026-11-25 environment), nor the
    # film: a peak GP of the curvature on 30 fake records called every row of a refine round's
    # front too bent, so the film constraint reads the GRU here (the peak GPs of Fp and jitter
    # keep that code path covered)
    m3f = {
        **raw_params["robots"]["mst_m3f"],
        "landing_tolerance": None,
        "retouch_allowed": None,
        "body_acc_limit": None,
    }
    mst_q = {**raw_params["robots"]["mst_q"], "retouch_allowed": None}
    data["robots"] = {**raw_params["robots"], "mst_m3f": m3f, "mst_q": mst_q}
    data["train"] = {  # both losses, so the DILATE path and the comparison stay covered
        **raw_params["train"],
        "hidden": 6,
        "epochs": 2,
        "batch": 16,
        "losses": ["dilate", "mse"],
        "peaks": ["Fp", "jitter"],
    }
    params = write_params(tmp / "params.yaml", data)
    (tmp / "acq").mkdir()
    from tests.data.fake import fake_acquisition

    pq.write_table(fake_acquisition(30, failed=0), tmp / "acq" / "samples.parquet")
    ds = dataset_args(tmp, tmp / "acq", params=params)
    assert CliRunner().invoke(app, ds).exit_code == 0
    uri = f"sqlite:///{tmp / 'mlflow.db'}"
    train_models(tmp, uri, data, "models")
    return tmp, uri, data


def train_models(tmp: Path, uri: str, data: dict, name: str) -> Path:
    """Run `ftfof train` on ``tmp/ds`` with ``data`` as params into ``tmp/<name>``."""
    params = write_params(tmp / f"{name}.yaml", data)
    args = cli_args(
        "train",
        params,
        dataset=tmp / "ds",
        out=tmp / name,
        metrics=tmp / f"{name}.json",
        loss_plot=tmp / f"{name}_loss.png",
        pred_plot=tmp / f"{name}_pred.png",
    )
    result = CliRunner().invoke(
        app, args, env={"MLFLOW_TRACKING_URI": uri, "DVC_EXP_NAME": "test-exp"}
    )
    assert result.exit_code == 0, result.stderr
    return tmp / name
