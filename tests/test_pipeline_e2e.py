"""The whole pipeline from a clean copy: `dvc repro` on the tiny profile, twice, and experiments.

Slow (a few minutes): CI runs it with `-m slow`.
"""

import json
import re
from pathlib import Path

import mlflow
import pyarrow.parquet as pq
import pytest
import yaml

from tests.pipeline import clone_to, run

pytestmark = pytest.mark.slow

STAGES = ("sample", "acquire", "dataset", "train", "optimize", "refine", "polish", "evaluate")
REPRODUCIBLE = {
    "sample": "data/trajectories.parquet",
    "acquire": "data/acquisition",
    "dataset": "data/dataset",
    "train": "data/models",
    "optimize": "data/optimize",
    "refine": "data/refine",
    "polish": "data/polish",
}


def _out_hashes(repo) -> dict[str, str]:
    lock = yaml.safe_load((repo / "dvc.lock").read_text())["stages"]
    return {
        stage: next(o["md5"] for o in lock[stage]["outs"] if o["path"] == path)
        for stage, path in REPRODUCIBLE.items()
    }


@pytest.fixture(scope="module")
def repo(tmp_path_factory):
    repo = clone_to(tmp_path_factory.mktemp("pipeline"))
    run(repo, "python", "-m", "ftfof", "profile", "tiny")
    run(repo, "git", "commit", "-q", "-am", "tiny profile")
    run(repo, "dvc", "repro", timeout=600)
    return repo


def test_every_stage_wrote_its_outputs(repo):
    assert pq.read_table(repo / "data/trajectories.parquet").num_rows == 40
    acquisition = pq.read_table(repo / "data/acquisition/samples.parquet")
    assert acquisition.num_rows == 44  # 40 sampled + 4 baselines
    assert pq.read_table(repo / "data/dataset/samples.parquet").num_rows >= 42
    assert {"surrogate_mse.pt", "config.json"} <= {p.name for p in (repo / "data/models").iterdir()}
    optimum = json.loads((repo / "data/optimize/optimum.json").read_text())
    assert max(optimum["recheck"]["violation"].values()) <= 0
    rounds = json.loads((repo / "reports/refine.json").read_text())["rounds"]
    assert 1 <= len(rounds) <= 2  # the tiny profile's refine.rounds, fewer once the target is met
    refined = pq.read_table(repo / "data/refine/dataset/samples.parquet").to_pandas()
    for r in rounds:
        assert (refined.source == f"refine:{r['round']}").sum() == r["added"]
    polish = json.loads((repo / "reports/polish.json").read_text())
    # the tiny search may find no rule-keeping offspring to simulate; the confirmation always runs
    assert polish["polished"] and polish["front"]
    evaluated = json.loads((repo / "data/polish/optimize/optimum.json").read_text())
    metrics = json.loads((repo / "reports/metrics.json").read_text())
    assert evaluated["front_row"] == metrics["optimum_front_row"]
    assert evaluated["origin"] == metrics["optimum_origin"]
    order = ["polynomial", "cycloidal", "random_bezier", "eps_bezier", "paper_optimum", "optimum"]
    assert set(metrics["table"]) == set(order)
    for row in metrics["table"].values():
        for column in (
            "peak_pull",
            "peak_normal",
            "peak_shear",
            "peak_pre_pressure",
            "jitter",
            "landing_pre_pressure",
        ):
            assert column in row and f"{column}_change" in row
        assert "peak_body_acc" in row and "min_bend_radius_change" in row
    html = (repo / "reports/evaluate.html").read_text()
    assert "Table I analogue" in html and "http" not in html
    # the report's table: the reference first, then the baselines, the paper's optimum and ours
    table = html[html.index("Table I analogue") :]
    rows = re.findall(r'<tr(?: class="optimum")?><td>(\w+)</td>', table)
    assert rows[: len(order)] == order
    assert (repo / "reports/optimum_trajectory.csv").read_text().startswith("t [s],")
    status = run(repo, "dvc", "status")
    assert "up to date" in status.stdout


def test_mlflow_store_holds_every_tracked_stage(repo):
    client = mlflow.MlflowClient(tracking_uri=f"sqlite:///{repo / 'mlflow.db'}")
    experiment = client.get_experiment_by_name("ftfof-mst_m3f")
    assert experiment.tags["mlflow.experimentKind"] == "custom_model_development"
    runs = client.search_runs([experiment.experiment_id])
    names = {r.info.run_name for r in runs}
    assert {"train", "optimize", "refine", "polish", "evaluate"} <= names
    evaluate = next(r for r in runs if r.info.run_name == "evaluate")
    polish = client.get_run(evaluate.data.tags["ftfof.optimize_run"])
    assert polish.info.run_name == "polish"
    refine = client.get_run(polish.data.tags["ftfof.optimize_run"])
    assert refine.info.run_name == "refine"
    optimize = client.get_run(refine.data.tags["ftfof.optimize_run"])
    assert optimize.info.run_name == "optimize"
    train = client.get_run(optimize.data.tags["ftfof.surrogate_run"])
    assert train.info.run_name == "train"
    assert all(r.data.tags["dvc.stage"] in STAGES for r in runs if "dvc.stage" in r.data.tags)


def test_champion_resolves_to_the_model_that_produced_the_optimum(repo, tmp_path):
    """`models:/ftfof-<robot>-<loss>@champion` holds the surrogates reports/metrics.json names:
    refine's fine-tuned version when a round changed train's models, else train's."""
    from ftfof.digests import file_sha256, models_digest
    from ftfof.surrogate.store import weights_file

    record = json.loads((repo / "reports/metrics.json").read_text())["model"]
    assert record["models_digest"] == models_digest(repo / "data/refine/models")
    uri = f"sqlite:///{repo / 'mlflow.db'}"
    name = f"ftfof-mst_m3f-{record['loss']}"
    mlflow.set_tracking_uri(uri)
    local = mlflow.artifacts.download_artifacts(f"models:/{name}@champion", dst_path=str(tmp_path))
    weights = Path(local) / "extra_files" / weights_file(record["loss"])
    assert file_sha256(weights) == record["weights_sha256"]
    client = mlflow.MlflowClient(tracking_uri=uri)
    champion = client.get_model_version_by_alias(name, "champion")
    fine_tuned = models_digest(repo / "data/refine/models") != models_digest(repo / "data/models")
    made_by = client.get_run(champion.run_id).data.tags["mlflow.source.name"]
    assert made_by == ("refine" if fine_tuned else "train")
    experiment = client.get_experiment_by_name("ftfof-mst_m3f")
    evaluate = client.search_runs(
        [experiment.experiment_id],
        "attributes.run_name = 'evaluate' AND attributes.status = 'FINISHED'",
        order_by=["attributes.start_time DESC"],
    )[0]
    assert evaluate.data.tags["ftfof.model"] == f"models:/{name}/{champion.version}"


def test_forced_rerun_at_another_commit_reproduces_every_artefact(repo):
    before = _out_hashes(repo)
    with (repo / "README.md").open("a") as readme:  # a new commit that changes no input
        readme.write("\nA line that no stage reads.\n")
    run(repo, "git", "commit", "-q", "-am", "another commit, same inputs")
    run(repo, "dvc", "repro", "--force", timeout=600)
    assert _out_hashes(repo) == before


def test_a_queued_sweep_runs_in_parallel_workers_and_compares(repo):
    # `ftfof sweep` queues the product (every setting named) and runs it with `dvc queue start
    # -j 2`; the workers run in temporary copies under .dvc/tmp and here see no
    # MLFLOW_TRACKING_URI: their runs must still land in the repository's own store. The painted
    # wall: MST-Q's straight-up peel keeps fc there (on acrylic and glass no path of it does)
    sweep = ("sweep", "robots=mst_q,mst_m3f", "surfaces=painted_wall", "--jobs", "2", "--poll", "2")
    out = run(repo, "python", "-m", "ftfof", *sweep, timeout=1500, unset=("MLFLOW_TRACKING_URI",))
    assert (
        "mst_q-painted_wall" in out.stdout and "mst_m3f-painted_wall" in out.stdout
    )  # the key columns
    rows = [line for line in out.stdout.splitlines() if line.startswith("| mst_")]
    assert len(rows) == 2 and all("?" not in row and len(row) < 200 for row in rows), rows
    shown = json.dumps(json.loads(run(repo, "dvc", "exp", "show", "--json").stdout))
    assert '"mst_q-painted_wall"' in shown and '"mst_m3f-painted_wall"' in shown
    diff = run(
        repo, "dvc", "metrics", "diff", "--json", "mst_q-painted_wall", "mst_m3f-painted_wall"
    )
    # the summaries only: a few figures per stage, not the full reports' hundreds
    compared = json.loads(diff.stdout)
    assert "optimum.peak_detachment" in compared["reports/summary/evaluate.json"]
    assert "reports/metrics.json" not in compared
    # MST-Q detaches straight up: the polynomial and the cycloid break its rules (FTFOF §VII), so
    # its Table I is taken against a trajectory it can run
    quad_metrics = json.loads(
        run(repo, "git", "show", f"{_rev(shown, 'mst_q-painted_wall')}:reports/metrics.json").stdout
    )
    broken = quad_metrics["robot_rules_broken"]
    assert any("md_path" in rule for rule in broken["polynomial"]), broken
    assert any("md_path" in rule for rule in broken["cycloidal"]), broken
    assert quad_metrics["reference"] not in ("polynomial", "cycloidal")
    assert broken[quad_metrics["reference"]] == []
    run(
        repo,
        "dvc",
        "plots",
        "diff",
        "mst_q-painted_wall",
        "mst_m3f-painted_wall",
        "-o",
        "plots_html",
    )
    page = (repo / "plots_html/index.html").read_text()
    assert "<img" in page and "http" not in page  # PNG plots, readable offline
    client = mlflow.MlflowClient(tracking_uri=f"sqlite:///{repo / 'mlflow.db'}")
    quad = client.get_experiment_by_name("ftfof-mst_q")
    (run_q,) = client.search_runs([quad.experiment_id], "attributes.run_name = 'optimize'")
    assert run_q.data.tags["dvc.exp_name"] == "mst_q-painted_wall"
    m3f = client.get_experiment_by_name("ftfof-mst_m3f")
    on_wall = client.search_runs(
        [m3f.experiment_id], "tags.`dvc.exp_name` = 'mst_m3f-painted_wall'"
    )
    assert {r.info.run_name for r in on_wall} >= {"train", "optimize", "refine", "evaluate"}
    assert all(r.data.params.get("surface", "painted_wall") == "painted_wall" for r in on_wall)
    # each experiment registered under its own alias; the workspace's champion is not theirs
    mine = client.get_model_version_by_alias("ftfof-mst_m3f-mse", "exp-mst_m3f-painted_wall")
    assert client.get_run(mine.run_id).data.tags["dvc.exp_name"] == "mst_m3f-painted_wall"
    for version in client.search_model_versions("name = 'ftfof-mst_m3f-mse'"):
        if "champion" in version.aliases:
            assert "dvc.exp_name" not in client.get_run(version.run_id).data.tags


def _rev(shown: str, name: str) -> str:
    """The commit of the experiment ``name`` in `dvc exp show --json` output."""

    def walk(node):
        if isinstance(node, dict):
            if node.get("name") == name and isinstance(node.get("rev"), str):
                yield node["rev"]
            for value in node.values():
                yield from walk(value)
        elif isinstance(node, list):
            for value in node:
                yield from walk(value)

    return next(walk(json.loads(shown)))
