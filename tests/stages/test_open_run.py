"""`ftfof.open_run`: a finished run for a notebook, as DataFrames and the report's figures."""

from __future__ import annotations

import json
import shutil

import pytest

import ftfof
from ftfof.errors import DataError

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def clone(evaluated, tmp_path_factory):
    """The evaluated tiny run laid out as `dvc repro` leaves it in a clone."""
    work = evaluated[0]
    root = tmp_path_factory.mktemp("clone")
    shutil.copytree(work / "polish" / "optimize", root / "data" / "polish" / "optimize")
    shutil.copytree(work / "sims", root / "data" / "evaluate")
    (root / "reports").mkdir()
    shutil.copy(work / "metrics.json", root / "reports" / "metrics.json")
    return root


def test_a_run_reads_as_the_report_shows_it(clone):
    run = ftfof.open_run(clone)
    metrics = json.loads((clone / "reports" / "metrics.json").read_text())
    assert run.reference == metrics["reference"]
    assert run.table.loc["optimum", "peak_pull"] == metrics["table"]["optimum"]["peak_pull"]
    assert run.changes.loc[run.reference, "peak_pull"] == 0.0
    assert list(run.fidelity.index) == list(metrics["fidelity"])
    assert run.decision().shape == (12,)
    for figure in (run.plot_trajectories(), run.plot_forces(), run.plot_jitter(), run.plot_front()):
        assert figure.axes  # the report's own figures, drawn


def test_a_clone_without_a_run_names_the_command_to_run(tmp_path):
    with pytest.raises(DataError, match="run `ftfof polish` first"):
        ftfof.open_run(tmp_path / "data" / "..")
