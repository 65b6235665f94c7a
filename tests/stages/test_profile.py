"""`ftfof profile`: overlays a profile on params.yaml, keeps comments, refuses bad profiles."""

import shutil

import pytest
import yaml
from typer.testing import CliRunner

from stages.cli import app
from tests.conftest import ROOT

runner = CliRunner()


def _setup(tmp_path, profile_text: str | None = None):
    params = tmp_path / "params.yaml"
    shutil.copy(ROOT / "params.yaml", params)
    profiles = tmp_path / "profiles"
    shutil.copytree(ROOT / "profiles", profiles)
    if profile_text is not None:
        (profiles / "bad.yaml").write_text(profile_text)
    return params, profiles


def _apply(params, profiles, name):
    return runner.invoke(app, ["profile", name, "-p", str(params), "--profiles", str(profiles)])


def test_tiny_profile_sets_its_values_and_keeps_everything_else(tmp_path):
    params, profiles = _setup(tmp_path)
    before = yaml.safe_load(params.read_text())
    result = _apply(params, profiles, "tiny")
    assert result.exit_code == 0, result.output
    after = yaml.safe_load(params.read_text())
    tiny = yaml.safe_load((profiles / "tiny.yaml").read_text())
    _overlay(before, tiny)
    assert after == before  # the profile's values (at any depth), nothing else changed
    assert after["robots"]["mst_m3f"]["landing_tolerance"] is None
    assert after["robots"]["mst_m3f"]["retouch_allowed"] is None
    assert after["robots"]["mst_m3f"]["pre_pressure"] == 5.0
    text = params.read_text()
    assert "# FTFOF §VI.C" in text and "platform: &m3f_platform\n" in text  # comments, anchors
    assert "scheduler: null" in text and max(map(len, text.splitlines())) > 95  # no re-wrap


def test_unknown_profile_is_named(tmp_path):
    params, profiles = _setup(tmp_path)
    result = _apply(params, profiles, "huge")
    assert result.exit_code != 0 and "no such profile" in result.output and "tiny" in result.output


@pytest.mark.parametrize(
    ("profile", "named"),
    [("sample:\n  n: -5\n", "sample.n"), ("sampel:\n  n: 5\n", "sampel")],
    ids=["invalid value", "misspelt section"],
)
def test_bad_profile_is_named_and_leaves_params_untouched(tmp_path, profile, named):
    params, profiles = _setup(tmp_path, profile)
    original = params.read_text()
    result = _apply(params, profiles, "bad")
    assert result.exit_code != 0 and named in result.output
    assert params.read_text() == original


def _overlay(target: dict, overlay: dict) -> None:
    for key, value in overlay.items():
        if isinstance(value, dict):
            _overlay(target[key], value)
        else:
            target[key] = value


def test_undo_puts_back_the_file_before_the_first_profile(tmp_path):
    params, profiles = _setup(tmp_path)
    original = params.read_bytes()
    assert _apply(params, profiles, "tiny").exit_code == 0
    assert _apply(params, profiles, "tiny").exit_code == 0  # a second profile keeps the first's
    assert params.read_bytes() != original
    result = runner.invoke(app, ["profile", "--undo", "-p", str(params)])
    assert result.exit_code == 0, result.output
    assert params.read_bytes() == original
    assert not (tmp_path / "params.yaml.before-profile").exists()
    result = runner.invoke(app, ["profile", "--undo", "-p", str(params)])
    assert result.exit_code == 2 and "no profile to undo" in result.stderr
    result = runner.invoke(app, ["profile", "tiny", "--undo", "-p", str(params)])
    assert result.exit_code == 2 and "give a profile name, or --undo alone" in result.stderr
    assert params.read_bytes() == original
