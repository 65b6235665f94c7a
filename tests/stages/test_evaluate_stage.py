"""Stage `evaluate`: a self-contained report, metrics, the controller CSV and an MLflow run."""

import base64
import copy
import io
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

from stages.cli import app
from tests.conftest import cli_args, write_params

ROWS = ("polynomial", "cycloidal", "random_bezier", "eps_bezier", "paper_optimum", "optimum")

runner = CliRunner()
pytestmark = pytest.mark.integration


def test_report_is_self_contained_and_every_image_decodes(evaluated):
    work, *_ = evaluated
    html = (work / "report.html").read_text()
    assert not re.search(r"(?:https?:)?//[a-z0-9.-]+\.[a-z]{2,}", html, re.I), "external URL"
    sources = re.findall(r"""<img[^>]+src=["']([^"']+)["']""", html)
    # paths (in the run-this box and with the figures), forces, jitter, the climb's traces and
    # side view, the slip comparison, the ε study, the choice, fidelity, refinement, 3 Pareto,
    # 2 training
    assert len(sources) == 16
    for src in sources:
        assert src.startswith("data:image/png;base64,")
        image = Image.open(io.BytesIO(base64.b64decode(src.split(",", 1)[1])))
        image.verify()
    assert not re.search(r"""(?:href|src)=["'](?!data:|#)""", html)
    for name in ROWS:
        assert f"<td>{name}</td>" in html
    assert "How the optimum was chosen" in html
    chosen = json.loads((work / "metrics.json").read_text())["optimum_front_row"]
    assert f"<td>{chosen} (optimum)</td>" in html  # in the choice's table and the front's


def test_the_climbing_robot_climbs_table_ones_trajectories(evaluated):
    """One swing each (the fixture's climb.steps): every Table I trajectory the robot can run is
    climbed, its figures in metrics.json, its row and the optimum's traces in the report."""
    work, *_ = evaluated
    metrics = json.loads((work / "metrics.json").read_text())
    climbed = metrics["climb"]
    assert set(climbed) == set(ROWS)  # MST-M3F can run every one of them
    for name in ROWS:
        c = climbed[name]
        assert c["steps_done"] == 1 and c["fell"] is False and c["error"] == ""
        assert 0 < c["jitter"] <= c["jitter_step"] and c["peak_pull"] > 1.0
    assert json.loads((work / "climb.json").read_text()) == climbed  # the climb stage's table
    written = {p.name for p in (work / "climb").glob("*.json")}
    assert written == {f"{n}.json" for n in ROWS} | {"manifest.json"}
    html = (work / "report.html").read_text()
    assert "<h2>The climbing robot</h2>" in html and "1 of 1" in html
    assert "FTFOF Table I [m/s²]" in html and "<td>327.3</td>" in html


def test_the_slip_comparison_is_in_the_metrics_and_the_report(evaluated):
    """evaluate.slip_scenario (HR onto the dusty wall at 4 s) under each controller: its
    figures in metrics.json, its table and figure in the report, its climbs written."""
    work, *_ = evaluated
    slip = json.loads((work / "metrics.json").read_text())["slip"]
    assert set(slip) == {"none", "weights", "replan", "both"}
    errors = {"mu_error", "adhesion_error"}
    for row in slip.values():
        figures = {"slip_distance", "slip_path", "max_slip_velocity", "fell", "estimated_slips"}
        assert set(row) == figures | errors
        assert 0 <= row["slip_distance"] <= row["slip_path"] and row["fell"] is False
        # the estimator's median errors over its slips: none (null) where it declared none
        assert all((row[k] is None) == (row["estimated_slips"] == 0) for k in errors)
    out = work / "slip_comparison"
    assert (out / "slip_eps_bezier.controllers.png").exists()
    assert {p.name for p in out.glob("slip_eps_bezier.*.json")} == {
        f"slip_eps_bezier.{c}.json" for c in [*slip, "controllers"]
    }
    html = (work / "report.html").read_text()
    section = html.split("<h2>Climbing under slip: the four controllers</h2>")[1].split("<h2>")[0]
    assert "HR's pad moved onto" in section and "dusty_wall at 1 s" in section
    assert [f"<tr><td>{c}</td>" in section for c in slip] == [True] * 4
    assert "<th>μ error</th><th>F_adh error</th><th>slips estimated</th>" in section
    assert 'alt="the changed foot\'s slip under each controller"' in section


def test_the_eps_study_is_in_the_metrics_and_the_report(evaluated):
    """The ε-Bezier re-timed at every ``study.eps``: each ε's landing in metrics.json, its row
    and the figure in the report."""
    work, *_ = evaluated
    study = json.loads((work / "metrics.json").read_text())["eps_study"]
    eps = [p["eps"] for p in study["points"]]
    assert eps == [0.0, 0.5, 1.0, 2.0, 4.0, 8.0]  # the default sweep, in order
    for p in study["points"]:
        assert p["landing_pre_pressure"] > 0.5 * study["press_target"] and p["landing_rate"] > 0
    assert study["trend"]["landing_pre_pressure"]["figure"] == "landing_pre_pressure"
    html = (work / "report.html").read_text()
    section = html.split("<h2>The ε-Bezier's landing against ε</h2>")[1].split("<h2>")[0]
    assert [f"<tr><td>{e:g}</td>" in section for e in eps] == [True] * len(eps)
    assert 'alt="the landing against ε"' in section


def test_the_choice_is_among_the_polished_candidates_as_the_simulator_measured_them(evaluated):
    work, *_ = evaluated
    choice = json.loads((work / "metrics.json").read_text())["choice"]
    assert choice["candidates"] >= 1 and choice["runs"] == 5  # nominal + 4 fresh copies
    assert sum(choice["removed_by"].values()) == choice["candidates"] - 1
    assert set(choice["chosen"]) == {"fs1", "fsj", "fs3", "fs7", "fs2", "fs5"}
    for name, value in choice["chosen"].items():
        assert choice["lowest"][name] <= value


def test_metrics_table_and_controller_export(evaluated):
    work, *_ = evaluated
    metrics = json.loads((work / "metrics.json").read_text())
    table = metrics["table"]
    assert set(table) == set(ROWS)
    assert table["polynomial"]["peak_detachment_change"] == 0.0
    assert table["polynomial"]["peak_pull_change"] == 0.0
    for row in table.values():
        assert row["peak_detachment"] > 0 and row["peak_body_acc"] > 0
    # the two front members: the polished optimum is the simulator's, not the surrogates'
    assert metrics["optimum_origin"] == "polish"
    assert metrics["fidelity_points"] == 2
    front = metrics["front_simulated"]
    assert len(front["members"]) == 3 and front["members"][0]["optimum"]
    assert front["film_safe_fraction"] == pytest.approx(
        sum(m["min_bend_radius"] >= front["film_limit"]["limit"] for m in front["members"]) / 3,
        abs=1e-4,
    )
    assert front["film_limit"]["limit"] == front["film_limit"]["fc"] == 0.006
    for row in table.values():  # every row of the table says how tightly it bends the film
        assert row["min_bend_radius"] > 0
    # every run again on the check film: the optimum, the front members and Table I's rows
    films = metrics["film_check"]
    assert films["nodes"] == 40 and films["check_nodes"] == 80 and not films["missing"]
    assert set(films["radius"]) == {*ROWS, *(f"front {m['row']}" for m in front["members"][1:])}
    for m in front["members"]:
        assert (
            m["min_bend_radius_on_check_film"]
            == films["radius"]["optimum" if m["optimum"] else f"front {m['row']}"][1]
        )
    for row in table.values():  # the detachment-window jitter never exceeds the whole run's peak
        assert 0 < row["jitter"] <= row["peak_body_acc"] + 1e-9
    assert metrics["seconds"] > 0
    assert {"fs1", "fs3", "fs7"} <= set(metrics["fidelity"])
    csv = np.loadtxt(work / "optimum.csv", delimiter=",", skiprows=1)
    header = (work / "optimum.csv").read_text().splitlines()[0]
    assert header.startswith("t [s],x [m],z [m],vx [m/s],vz [m/s],q1 [rad]")
    assert csv.shape[1] == 11 and np.allclose(np.diff(csv[:, 0]), 1 / 200)
    assert metrics["export"]["rows"] == csv.shape[0]


def test_table_one_is_simulated_again_at_the_check_step(evaluated):
    work, *_ = evaluated
    metrics = json.loads((work / "metrics.json").read_text())
    check = metrics["step_check"]
    assert check["step"] == 5e-4 and check["check_step"] == 1.25e-4
    assert set(check["table"]) == set(ROWS)
    optimum = check["table"]["optimum"]
    # the acquisition step's figures are Table I's own
    assert optimum["peak_pull"][0] == pytest.approx(metrics["table"]["optimum"]["peak_pull"])
    assert optimum["jitter"][0] == pytest.approx(metrics["table"]["optimum"]["jitter"])
    for name, shift in check["shift"].items():
        before, after = optimum[f"{name}_change"]
        assert shift == pytest.approx(after - before, abs=0.02)
    assert "Does it hold at a finer solver step?" in (work / "report.html").read_text()


def test_mlflow_run_links_the_run_that_passed_its_optimum_on(evaluated):
    _, uri, _, _ = evaluated
    import mlflow

    client = mlflow.MlflowClient(tracking_uri=uri)
    experiment = client.get_experiment_by_name("ftfof-mst_m3f")
    (run,) = client.search_runs([experiment.experiment_id], "attributes.run_name = 'evaluate'")
    polish = client.get_run(run.data.tags["ftfof.optimize_run"])
    assert polish.info.run_name == "polish"
    assert polish.data.tags["ftfof.optimum_digest"] == run.data.tags["ftfof.optimum_digest"]
    refine = client.get_run(polish.data.tags["ftfof.optimize_run"])  # refine, with no rounds here
    assert refine.info.run_name == "refine"
    source = client.get_run(refine.data.tags["ftfof.optimize_run"])
    assert source.info.run_name == "optimize"
    assert source.data.tags["ftfof.optimum_digest"] == refine.data.tags["ftfof.optimum_digest"]
    assert "table.optimum.peak_detachment_change" in run.data.metrics
    artifacts = {a.path for a in client.list_artifacts(run.info.run_id, "report")}
    assert "report/report.html" in artifacts


def test_an_optimum_of_another_robot_is_refused(evaluated):
    work, uri, data, evaluate = evaluated
    other = copy.deepcopy(data)
    other["robot"] = "mst_q"
    write_params(work / "params.yaml", other)
    result = runner.invoke(app, evaluate, env={"MLFLOW_TRACKING_URI": uri})
    write_params(work / "params.yaml", data)
    assert result.exit_code != 0 and "params select 'mst_q'" in result.output


def test_missing_figure_and_other_models_are_refused_before_simulating(evaluated, tmp_path):
    _, uri, _, evaluate = evaluated
    env = {"MLFLOW_TRACKING_URI": uri}
    empty = tmp_path / "figures"
    empty.mkdir()
    args = [*evaluate, "--figures", str(empty), "--out", str(tmp_path / "sims")]
    result = runner.invoke(app, args, env=env)
    assert result.exit_code != 0 and "optimize_star.png" in result.output
    models = tmp_path / "models"
    shutil.copytree(evaluate[evaluate.index("--models") + 1], models)
    config = models / "config.json"
    config.write_text(config.read_text() + "\n")
    args = [*evaluate, "--models", str(models), "--out", str(tmp_path / "sims")]
    result = runner.invoke(app, args, env=env)
    assert result.exit_code != 0 and "other models" in result.output
    assert not (tmp_path / "sims").exists()  # refused before any simulation


def test_an_optimum_from_an_older_version_is_refused_by_its_missing_fields(evaluated, tmp_path):
    _, uri, _, evaluate = evaluated
    old = tmp_path / "optimize"
    shutil.copytree(evaluate[evaluate.index("--optimize") + 1], old)
    optimum = json.loads((old / "optimum.json").read_text())
    del optimum["simulator_check"], optimum["rhs"]["rows"]  # as a version before the check wrote
    (old / "optimum.json").write_text(json.dumps(optimum))
    args = [*evaluate, "--optimize", str(old), "--out", str(tmp_path / "sims")]
    result = runner.invoke(app, args, env={"MLFLOW_TRACKING_URI": uri})
    assert result.exit_code != 0
    assert "lacks simulator_check, rhs.rows" in result.output and "ftfof optimize" in result.output
    assert not (tmp_path / "sims").exists()


def test_champion_resolves_to_the_model_that_produced_the_optimum(evaluated, tmp_path):
    """The acceptance check of issue 37: `models:/ftfof-<robot>-<loss>@champion` holds the
    surrogates reports/metrics.json names, and the evaluate and polish runs name that version."""
    work, uri, data, _ = evaluated
    import mlflow

    from ftfof.digests import file_sha256
    from ftfof.surrogate.store import weights_file

    record = json.loads((work / "metrics.json").read_text())["model"]
    assert record["weights_sha256"] == file_sha256(work / "refine" / "models" / weights_file("mse"))
    name, alias = f"ftfof-mst_m3f-{record['loss']}", data["train"]["alias"]
    mlflow.set_tracking_uri(uri)
    local = Path(
        mlflow.artifacts.download_artifacts(f"models:/{name}@{alias}", dst_path=str(tmp_path))
    )
    assert (
        file_sha256(local / "extra_files" / weights_file(record["loss"]))
        == (record["weights_sha256"])
    )
    client = mlflow.MlflowClient(tracking_uri=uri)
    champion = client.get_model_version_by_alias(name, alias)
    experiment = client.get_experiment_by_name("ftfof-mst_m3f")
    run = client.search_runs(  # the latest: tests before this one evaluated again
        [experiment.experiment_id],
        "attributes.run_name = 'evaluate' AND attributes.status = 'FINISHED'",
        order_by=["attributes.start_time DESC"],
    )[0]
    assert run.data.tags["ftfof.model"] == f"models:/{name}/{champion.version}"
    polish = client.get_run(run.data.tags["ftfof.optimize_run"])
    assert polish.data.tags["ftfof.model"] == run.data.tags["ftfof.model"]
    # the runs span the work they record: opened before it, not after
    for stage_run, seconds in (
        (run, json.loads((work / "metrics.json").read_text())["seconds"]),
        (polish, json.loads((work / "polish.json").read_text())["seconds"]),
    ):
        assert stage_run.info.end_time - stage_run.info.start_time >= 800 * seconds


def test_where_the_optimum_falls_the_next_candidates_climb_and_the_report_says_so(
    evaluated, tmp_path
):
    """A fall at the first millimetre off plan (climb.fall_distance 1 µm) fells every climb:
    the optimum's, then each candidate's tried by RHS's order, at most climb.fallbacks, one at
    a time; climb.json says so, the report says so, and the export stays RHS's choice."""
    work, uri, data, evaluate = evaluated
    data = copy.deepcopy(data)
    data["climb"] = {**data["climb"], "fall_distance": 1e-6, "fallbacks": 2}
    params = write_params(tmp_path / "params.yaml", data)
    for name in ("slip.json", "eps_study.json", "eps_study.png"):
        shutil.copy(work / name, tmp_path / name)
    shutil.copytree(work / "slip_comparison", tmp_path / "slip_comparison")
    optimize = work / "polish" / "optimize"
    climb = cli_args(
        "climb-table", params, optimize=optimize, out=tmp_path / "climb", record=tmp_path / "c.json"
    )
    result = runner.invoke(app, climb, env={"MLFLOW_TRACKING_URI": uri})
    assert result.exit_code == 0, result.output
    record = json.loads((tmp_path / "c.json").read_text())
    optimum = json.loads((optimize / "optimum.json").read_text())
    others = [r for r in optimum["rhs"]["rows"] if r != optimum["front_row"]]
    moved = record["moved_to"]
    assert record["optimum"]["fell"] and moved["row"] is None and moved["decision"] is None
    assert moved["why"].startswith("the optimum fell on the robot (")
    assert len(moved["tried"]) == min(2, len(others))
    for tried in moved["tried"]:
        assert tried["row"] in others and record[f"candidate_{tried['row']}"]["fell"]
        assert (tmp_path / "climb" / "fallbacks" / f"candidate_{tried['row']}").is_dir()
    shutil.copy(tmp_path / "c.json", tmp_path / "climb.json")
    args = list(evaluate)
    for option, value in (("-p", params), ("--out", tmp_path / "sims"),
                          ("--report", tmp_path / "report.html"),
                          ("--metrics", tmp_path / "metrics.json"),
                          ("--export", tmp_path / "optimum.csv")):  # fmt: skip
        args[args.index(option) + 1] = str(value)
    shutil.copytree(work / "sims", tmp_path / "sims")  # the same simulations: resumed
    result = runner.invoke(app, args, env={"MLFLOW_TRACKING_URI": uri})
    assert result.exit_code == 0, result.output
    html = (tmp_path / "report.html").read_text()
    assert "The choice moved:" in html and "No candidate tried climbs" in html
    assert (tmp_path / "optimum.csv").read_bytes() == (work / "optimum.csv").read_bytes()
