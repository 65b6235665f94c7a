"""The estimate of a whole `dvc repro` that acquire prints from its first samples."""

from __future__ import annotations

import shutil

import pytest
from typer.testing import CliRunner

from ftfof.pipeline import estimate
from ftfof.pipeline.estimate import REFERENCE_PACE, STAGES, FirstSamples, whole_run
from ftfof.pipeline.params_file import load_params
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
    assert whole_run(params, REFERENCE_PACE) == pytest.approx(565.0)  # 9 min 25 s
    assert whole_run(params, 2 * REFERENCE_PACE) == pytest.approx(1130.0)  # a slower machine
    stages = sum(s.tiny[1] for s in STAGES.values())
    assert whole_run(tiny, REFERENCE_PACE) == pytest.approx(estimate.OVERHEAD + stages)
    for name, stage in STAGES.items():  # the sizes the stages were measured at
        assert stage.size(params) == stage.committed[0], name
        assert stage.size(tiny) == stage.tiny[0], name


def test_a_larger_run_takes_longer_and_none_is_below_nothing(params):
    bigger = params.model_copy(update={"sample": params.sample.model_copy(update={"n": 2000})})
    assert whole_run(bigger, REFERENCE_PACE) > whole_run(params, REFERENCE_PACE) + 130
    off = params.evaluate.model_copy(update={"climb": False})
    assert STAGES["evaluate"].seconds(params.model_copy(update={"evaluate": off})) >= 0


def test_the_estimate_is_printed_once_after_ten_seconds_or_at_the_end(params, capsys):
    heard = FirstSamples(params, todo=1004)
    heard(16, 4.0)  # the first batches back: the pace counts from here
    heard(24, 6.1)
    assert capsys.readouterr().err == ""  # too early to tell
    heard(40, 10.3)  # 24 samples in 6.3 s since the first batches
    said = capsys.readouterr().err
    assert said.count("\n") == 1  # one line, also in a log
    assert said.startswith("estimate: 0.26 s per sample here (0.13 where `dvc repro` took 9 min")
    assert "the whole run should take about 19 min on these params" in said
    heard(80, 21.0)
    assert capsys.readouterr().err == ""
    short = FirstSamples(params, todo=16)
    short(16, 6.0)  # all back in one batch, before ten seconds: the pace since the start
    assert "0.38 s per sample here" in capsys.readouterr().err
