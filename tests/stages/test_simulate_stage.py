"""Stage `simulate`: one baseline on the simulated platform -> a CSV of every channel and a PNG."""

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

from ftfof.sim.records import CHANNELS
from stages.cli import app
from tests.conftest import ROOT, cli_args

pytestmark = pytest.mark.integration
runner = CliRunner()


def test_a_baseline_writes_every_channel_and_a_figure(tmp_path):
    args = cli_args("simulate", ROOT / "params.yaml", baseline="polynomial", out_dir=tmp_path)
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "polynomial: ok" in result.output
    csv = tmp_path / "polynomial.csv"
    header = csv.read_text().splitlines()[0]
    assert header.split(",") == list(CHANNELS)
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert data.ndim == 2 and data.shape[1] == len(CHANNELS) and data.shape[0] > 10
    assert np.all(np.isfinite(data)) and np.all(np.diff(data[:, 0]) > 0)  # t increases
    assert data[:, CHANNELS.index("Fd")].max() > 0  # the pad held and was pulled off
    with Image.open(tmp_path / "polynomial.png") as image:
        assert image.format == "PNG" and min(image.size) > 100


def test_an_unknown_baseline_or_two_sources_are_refused_without_output(tmp_path):
    args = cli_args("simulate", ROOT / "params.yaml", baseline="spline", out_dir=tmp_path)
    result = runner.invoke(app, args)
    assert result.exit_code != 0 and "unknown baseline 'spline'" in result.output
    args = cli_args("simulate", ROOT / "params.yaml", baseline="polynomial", row=0)
    result = runner.invoke(app, [*args, "--out-dir", str(tmp_path)])
    assert result.exit_code != 0 and "exactly one of" in result.output
    assert not any(tmp_path.iterdir())
