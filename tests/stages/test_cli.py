"""The `ftfof` command: help for the app and every sub-command, both entry points."""

import subprocess
import sys

import pytest
from typer.testing import CliRunner

from stages.cli import app
from tests.conftest import ROOT

pytestmark = pytest.mark.integration

runner = CliRunner()
COMMANDS = [c.name for c in app.registered_commands]


def test_app_help_lists_every_command():
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    for name in COMMANDS:
        assert name in result.stdout


@pytest.mark.parametrize("name", COMMANDS)
def test_each_command_has_help(name):
    result = runner.invoke(app, [name, "--help"])
    assert result.exit_code == 0
    assert "Usage" in result.stdout


def test_python_dash_m_and_console_script_agree():
    via_module = subprocess.run(
        [sys.executable, "-m", "ftfof", "--help"], cwd=ROOT, capture_output=True, text=True
    )
    assert via_module.returncode == 0
    for name in COMMANDS:
        assert name in via_module.stdout


def test_no_arguments_prints_help_and_fails():
    result = runner.invoke(app, [])
    assert result.exit_code == 2


def test_the_version_names_the_simulator_and_torch():
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0 and result.stdout.startswith("ftfof 0.")
    assert "exudyn 1." in result.stdout and "torch 2." in result.stdout


@pytest.mark.parametrize("name", COMMANDS)
def test_help_wraps_at_80_columns_and_cuts_nothing(name):
    result = runner.invoke(app, [name, "--help"], env={"COLUMNS": "80"}, terminal_width=80)
    assert result.exit_code == 0
    assert "…" not in result.stdout
    assert max(len(line) for line in result.stdout.splitlines()) <= 80
