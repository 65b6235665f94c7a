"""The estimate of a whole `dvc repro` from its stages' sizes and a machine's pace."""

from __future__ import annotations

import shutil

import pytest
from typer.testing import CliRunner

from ftfof.pipeline.estimate import sizes_of
from ftfof.pipeline.params_file import load_params
from ftfof.study import duration
from ftfof.study.duration import REFERENCE_PACE, STAGES, whole_run
from stages.cli import app
from tests.conftest import ROOT


@pytest.fixture
def tiny(tmp_path):
    params = tmp_path / "params.yaml"
    shutil.copy(ROOT / "params.yaml", params)
    result = CliRunner().invoke(app, ["profile", "tiny", "-p", str(params)])
    assert result.exit_code == 0, result.output
    return load_params(params)


def test_both_measured_runs_come_back_at_their_pace(params, tiny):
    committed, small = sizes_of(params), sizes_of(tiny)
    assert whole_run(committed, REFERENCE_PACE) == pytest.approx(1604.0)  # 26 min 44 s
    assert whole_run(committed, 2 * REFERENCE_PACE) == pytest.approx(3208.0)  # a slower machine
    stages = sum(s.tiny[1] for s in STAGES.values())
    assert whole_run(small, REFERENCE_PACE) == pytest.approx(duration.OVERHEAD + stages)
    for name, stage in STAGES.items():  # the sizes the stages were measured at
        assert committed[name] == stage.committed[0], name
        assert small[name] == stage.tiny[0], name


def test_a_larger_run_takes_longer_and_none_is_below_nothing(params):
    bigger = params.model_copy(update={"sample": params.sample.model_copy(update={"n": 2000})})
    larger = whole_run(sizes_of(bigger), REFERENCE_PACE)
    assert larger > whole_run(sizes_of(params), REFERENCE_PACE) + 130
    off = params.evaluate.model_copy(update={"climb": False})
    assert sizes_of(params.model_copy(update={"evaluate": off}))["evaluate"] == 0.0
    assert STAGES["evaluate"].seconds(0.0) == pytest.approx(110.4 - 310.5 * 10 / 70)  # >= 0
    assert STAGES["acquire"].seconds(-1e6) == 0.0  # never below nothing
