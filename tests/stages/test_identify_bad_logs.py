"""A bad slip log: one line naming file, row and column, a non-zero exit, nothing written."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
import yaml
from typer.testing import CliRunner

from stages.cli import app
from tests.conftest import ROOT

runner = CliRunner()


def _log(n: int = 40) -> pd.DataFrame:
    t = np.arange(2 * n) * 1e-3
    load = np.repeat([0.0, 2.0], n)
    ft = np.tile(np.r_[np.linspace(0, 9.9, n - 20), np.linspace(9.95, 10.0, 20)], 2) + 0.45 * load
    return pd.DataFrame({"t": t, "Fx": ft, "Fz": -load, "load": load})


@pytest.mark.parametrize(
    ("spoil", "where"),
    [
        (lambda df: df.drop(columns="Fz"), "row 1, column 'Fz': missing"),
        (lambda df: df.assign(t=np.r_[df.t[:10], df.t[9:-1]]), "row 12, column 't'"),
        (lambda df: df.iloc[:25], "column 'Fx': "),
    ],
    ids=["missing column", "time backwards", "too few slip samples"],
)
def test_a_bad_slip_log_is_refused_naming_file_row_and_column(tmp_path, spoil, where):
    path = tmp_path / "slip.csv"
    spoil(_log()).to_csv(path, index=False)
    report, folder = tmp_path / "identify.json", tmp_path / "identify"
    args = ["identify", "--surface", "glass", "--log", str(path), "--params"]
    args += [str(ROOT / "params.yaml"), "--report", str(report), "--folder", str(folder)]
    result = runner.invoke(app, args)
    assert result.exit_code != 0
    assert str(path) in result.output and where in result.output
    assert len(result.output.strip().splitlines()) == 1
    assert not report.exists() and not folder.exists()


def test_a_good_slip_log_is_identified(tmp_path):
    path = tmp_path / "slip.csv"
    _log().to_csv(path, index=False)
    report = tmp_path / "identify.json"
    args = ["identify", "--surface", "glass", "--log", str(path), "--params"]
    args += [str(ROOT / "params.yaml"), "--report", str(report)]
    args += ["--folder", str(tmp_path / "identify")]
    assert runner.invoke(app, args).exit_code == 0
    out = json.loads(report.read_text())
    assert out["source"] == str(path) and out["mu"]["truth"] is None
    assert abs(out["mu"]["least_squares"] - 0.45) < 0.05  # the synthetic log's slope
    block = yaml.safe_load((tmp_path / "identify" / "surface.yaml").read_text())["glass"]
    assert block["friction"] == round(out["mu"]["estimate"], 4)
    assert (tmp_path / "identify" / "convergence.png").stat().st_size > 0
    summary = json.loads((tmp_path / "summary" / "identify.json").read_text())
    assert summary["mu_estimate"] == out["mu"]["estimate"]


def _identify(tmp_path, *extra: str) -> dict:
    report = tmp_path / "identify.json"
    args = ["identify", *extra, "--params", str(ROOT / "params.yaml"), "--report", str(report)]
    result = runner.invoke(app, [*args, "--folder", str(tmp_path / "identify")])
    assert result.exit_code == 0, result.output
    return json.loads(report.read_text())


@pytest.mark.integration
@pytest.mark.parametrize("surface", ["glass", "acrylic", "painted_wall"])
def test_identify_simulate_recovers_the_preset_within_5_percent(tmp_path, surface):
    """The round trip of the contact law: mu, F_adh at the test's speed and F_adh,0."""
    out = _identify(tmp_path, "--surface", surface, "--simulate")
    for key in ("mu", "adhesion", "adhesion_0"):
        assert out[key]["estimate"] == pytest.approx(out[key]["truth"], rel=0.05), key
    assert out["adhesion"]["truth"] > out["adhesion_0"]["truth"]  # R(v) > 1
    assert set(out["adhesion"]) == {"estimate", "truth", "least_squares"}
    assert (tmp_path / "identify" / "convergence.png").stat().st_size > 0


@pytest.mark.integration
def test_two_drag_speeds_recover_the_rate_exponent(tmp_path):
    out = _identify(tmp_path, "--surface", "glass", "--simulate", "--speeds", "0.0005,0.001")
    law = out["rate_law"]
    assert law["speeds"] == [0.0005, 0.001] and law["adhesion"][0] < law["adhesion"][1]
    # n follows from the ratio of the two speeds' R - 1, which takes the estimates' 1-3 % error
    # of F_adh 2-3 times over: 0.353 against 0.4 on the plate's coupon (0.378 on the grip)
    assert law["exponent"]["estimate"] == pytest.approx(law["exponent"]["truth"], rel=0.15)
    # v* takes the error of R - 1 1 / n times over (docs/decisions/0027): on the plate's coupon
    # it comes out at 0.100 against 0.05 m/s, so it is reported, and held only to a factor 2.5
    ratio = law["rate_speed"]["estimate"] / law["rate_speed"]["truth"]
    assert 0.4 < ratio < 2.5, ratio


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--speeds", "0.001,0.002"], "with --simulate"),
        (["--simulate", "--speeds", "0.001"], "two distinct positive speeds"),
        (["--simulate", "--speeds", "fast,slow"], "is not two numbers"),
    ],
)
def test_bad_speeds_are_refused_before_anything_runs(tmp_path, extra, message):
    args = ["identify", "--surface", "glass", *extra, "--params", str(ROOT / "params.yaml")]
    result = runner.invoke(app, [*args, "--report", str(tmp_path / "identify.json")])
    assert result.exit_code != 0 and message in result.output
    assert not (tmp_path / "identify.json").exists()


def test_slip_logs_are_imported_for_identify_and_bad_ones_refused(tmp_path):
    good, bad = tmp_path / "wall.csv", tmp_path / "spoilt.csv"
    _log().to_csv(good, index=False)
    _log().drop(columns="load").to_csv(bad, index=False)
    out = tmp_path / "slip"
    base = ["import-logs", "--protocol", "slip", "--out", str(out)]
    result = runner.invoke(app, [*base, str(good), str(bad)])
    assert result.exit_code != 0 and str(bad) in result.output and "column 'load'" in result.output
    assert not out.exists()  # every log is checked before any is written
    result = runner.invoke(app, [*base, str(good)])
    assert result.exit_code == 0, result.output
    imported = pd.read_csv(out / "wall.csv")
    assert list(imported.columns) == ["t", "Fx", "Fz", "load"] and len(imported) == len(_log())
    args = ["identify", "--surface", "glass", "--log", str(out / "wall.csv"), "--params"]
    args += [str(ROOT / "params.yaml"), "--report", str(tmp_path / "r.json")]
    args += ["--folder", str(tmp_path / "identify")]
    assert runner.invoke(app, args).exit_code == 0


def test_an_unknown_log_protocol_is_refused(tmp_path):
    path = tmp_path / "wall.csv"
    _log().to_csv(path, index=False)
    result = runner.invoke(app, ["import-logs", "--protocol", "drag", str(path)])
    assert result.exit_code != 0 and "unknown protocol 'drag'" in result.output
