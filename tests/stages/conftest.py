"""Fixtures shared by the stage tests: an optimised, refined (no rounds), polished, climbed and
evaluated tiny run."""

import copy
import shutil

import pytest
from typer.testing import CliRunner

from stages.cli import app
from tests.conftest import cli_args, optimize_args, polish_args, refine_args, write_params

runner = CliRunner()
TINY_OPTIMIZE = {"population": 12, "generations": 4, "log_every": 2, "recheck_samples": 512}
TINY_POLISH = {"population": 4, "generations": 4}  # 2 made no offspring the rules let through


@pytest.fixture(scope="module")
def refined_tiny(trained, tmp_path_factory):
    """The tiny models optimised, and refine (no rounds) passing the optimum on: what polish
    starts from. (work, params path, MLflow env, params data, the train directory)"""
    return refine_tiny(trained, tmp_path_factory)


def refine_tiny(trained, tmp_path_factory):
    """:func:`refined_tiny`'s run, for a fixture of either scope."""
    tmp, uri, data = trained
    data = copy.deepcopy(data)
    data["optimize"] = {**data["optimize"], **TINY_OPTIMIZE}
    data["polish"] = {**data.get("polish", {}), **TINY_POLISH}
    scenario = {**data["evaluate"]["slip_scenario"], "time": 1.0}  # within one step's climb
    data["evaluate"] = {
        **data["evaluate"],
        "front_points": 2,
        "export_rate_hz": 200,
        "slip_scenario": scenario,
    }
    data["refine"] = {**data["refine"], "rounds": 0}
    data["acquire"] = {**data["acquire"], "workers": 2}
    data["climb"] = {**data.get("climb", {}), "steps": 1}  # evaluate climbs: one swing each
    work = tmp_path_factory.mktemp("evaluate")
    params = write_params(work / "params.yaml", data)
    figures = work / "figures"
    figures.mkdir()
    for source, target in (("loss", "train_loss"), ("pred", "train_predictions")):
        shutil.copy(tmp / f"models_{source}.png", figures / f"{target}.png")
    env = {"MLFLOW_TRACKING_URI": uri}
    result = runner.invoke(app, optimize_args(params, tmp / "models", work, figures), env=env)
    assert result.exit_code == 0, result.output
    refine = refine_args(
        params, tmp, work / "optimize", work / "refine", figures / "refine_fidelity.png"
    )
    result = runner.invoke(app, refine, env=env)  # refine.rounds: 0 passes the optimum on
    assert result.exit_code == 0, result.output
    return work, params, env, data, tmp


@pytest.fixture(scope="session")
def evaluated(trained, tmp_path_factory):
    """The tiny run polished, climbed, slipped, studied and evaluated: once for every module
    that reads it (each rebuilt it in 90 s before), on a refined run of its own (polish's tests
    polish theirs)."""
    work, params, env, data, _ = refine_tiny(trained, tmp_path_factory)
    figures = work / "figures"
    result = runner.invoke(app, polish_args(params, work / "refine", work / "polish"), env=env)
    assert result.exit_code == 0, result.output
    evaluate = cli_args(
        "evaluate",
        params,
        optimize=work / "polish" / "optimize",
        models=work / "refine" / "models",
        refine=work / "refine.json",
        figures=figures,
        out=work / "sims",
        report=work / "report.html",
        metrics=work / "metrics.json",
        export=work / "optimum.csv",
    )
    for robot_stage in (
        cli_args("climb-table", params, optimize=work / "polish" / "optimize", out=work / "climb",
                 record=work / "climb.json"),
        cli_args("slip", params, out=work / "slip_comparison", record=work / "slip.json"),
        ["study", *cli_args("eps", params, report=work / "eps_study.json",
                            figure=work / "eps_study.png")],
    ):  # fmt: skip
        result = runner.invoke(app, robot_stage, env=env)
        assert result.exit_code == 0, result.output
    result = runner.invoke(app, evaluate, env=env)
    assert result.exit_code == 0, result.output
    return work, env["MLFLOW_TRACKING_URI"], data, evaluate
