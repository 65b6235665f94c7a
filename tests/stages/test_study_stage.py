"""`ftfof study eps` on the default params: the ε-Bezier baseline at six ε on the platform, and
what the simulator says of the ε-Bezier paper's Fig. 15-16 (docs/simulator.md, "The ε study")."""

import json
from itertools import pairwise

import pytest
from PIL import Image
from typer.testing import CliRunner

from stages.cli import app
from tests.conftest import ROOT, cli_args

pytestmark = pytest.mark.integration
runner = CliRunner()


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("study")
    args = cli_args(
        "eps", ROOT / "params.yaml", report=out / "eps.json", figure=out / "eps.png", workers=2
    )
    result = runner.invoke(app, ["study", *args])
    assert result.exit_code == 0, result.output
    return json.loads((out / "eps.json").read_text()), out / "eps.png"


def test_the_landing_impact_falls_to_eps_4_and_flattens_to_8_as_the_seed_says(study):
    report, _ = study
    points = {p["eps"]: p for p in report["points"]}
    assert sorted(points) == [0.0, 0.5, 1.0, 2.0, 4.0, 8.0]
    peak = [points[e]["landing_pre_pressure"] for e in (0.0, 0.5, 1.0, 2.0, 4.0)]
    assert all(b < a for a, b in pairwise(peak)), peak
    assert abs(points[8.0]["landing_pre_pressure"] / points[4.0]["landing_pre_pressure"] - 1) < 0.1
    assert report["trend"]["landing_pre_pressure"]["agrees_with_seed"] is True
    # from ε = 4 the impact is the pressure the landing holds ("the supporting force")
    for e in (4.0, 8.0):
        assert points[e]["landing_pre_pressure"] < 1.05 * points[e]["held_pre_pressure"]
    assert points[0.0]["landing_pre_pressure"] > 1.5 * points[0.0]["held_pre_pressure"]


def test_a_larger_eps_lands_slower_and_shakes_the_body_less(study):
    report, _ = study
    points = {p["eps"]: p for p in report["points"]}
    # the rise rate keeps falling past 4 (the seed's figure shows force, not its rate)
    assert points[8.0]["landing_rate"] < 0.5 * points[4.0]["landing_rate"]
    assert points[4.0]["landing_rate"] < 0.5 * points[0.0]["landing_rate"]
    # the plate's toe lets go at once, so its release shakes the body too: the landing's share
    # falls from 21.0 to 11.2 m/s2 at 4 (0.53), not below half as on the grip foot (decision 0028)
    assert points[4.0]["peak_body_acc"] < 0.6 * points[0.0]["peak_body_acc"]
    # past 4 the landing is gentle and the toe's release sets the peak (11.2 / 11.9 m/s2)
    assert points[8.0]["peak_body_acc"] == pytest.approx(points[4.0]["peak_body_acc"], rel=0.1)


def test_the_figure_is_written(study):
    _, figure = study
    with Image.open(figure) as image:
        assert image.format == "PNG" and min(image.size) > 100


def test_a_bad_eps_list_is_one_line_and_writes_nothing(tmp_path):
    args = cli_args("eps", ROOT / "params.yaml", epsilons="1,-2", report=tmp_path / "e.json")
    result = runner.invoke(app, ["study", *args, "--figure", str(tmp_path / "e.png")])
    assert result.exit_code != 0 and "--epsilons" in result.output
    assert not any(tmp_path.iterdir())
