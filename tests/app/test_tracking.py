"""Run links: a run names the latest finished run that made its inputs, by a digest tag."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from ftfof.pipeline import tracking

ROOT = Path(__file__).resolve().parents[2]


class _Store:
    """The two MLflow calls a link makes, answered from a list of (run_id, run_name, tags)."""

    def __init__(self, runs: list[tuple[str, str, dict]], experiment_id: str = "7"):
        self.runs, self.experiment_id, self.filters = runs, experiment_id, []

    def search_runs(self, experiment_names, filter_string, order_by, max_results, output_format):
        self.filters.append(filter_string)
        hits = [
            SimpleNamespace(info=SimpleNamespace(run_id=run_id))
            for run_id, name, tags in reversed(self.runs)  # the latest first
            if f"run_name = '{name}'" in filter_string
            and all(f"tags.`{k}` = '{v}'" in filter_string for k, v in tags.items())
        ]
        return hits[:max_results]

    def get_experiment_by_name(self, name):
        return SimpleNamespace(experiment_id=self.experiment_id)


def test_a_link_without_a_matching_run_says_unknown_and_writes_no_note():
    store = _Store([("r1", "train", {tracking.MODELS_DIGEST_TAG: "other"})])
    link, run_id = tracking.link_tags(
        store, "e", "train", tracking.MODELS_DIGEST_TAG, "d1", tracking.SURROGATE_RUN_TAG, "S"
    )
    assert run_id is None
    assert link == {tracking.MODELS_DIGEST_TAG: "d1", tracking.SURROGATE_RUN_TAG: "unknown"}
    (query,) = store.filters
    assert "attributes.status = 'FINISHED'" in query and "tags.`" in query


def test_a_link_names_the_latest_matching_run_in_its_note():
    runs = [("r1", "train", {"digest": "d1"}), ("r2", "train", {"digest": "d1"})]
    runs.append(("r3", "optimize", {"digest": "d1"}))
    link, run_id = tracking.link_tags(_Store(runs), "e", "train", "digest", "d1", "link", "M", "!")
    assert run_id == "r2" and link["link"] == "r2" and link["digest"] == "d1"
    assert link["mlflow.note.content"] == "M: run [r2](#/experiments/7/runs/r2)!"


@pytest.mark.integration  # a real MLflow SQLite store (its schema migrations take seconds)
def test_link_tags_point_at_the_latest_matching_run(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("MLFLOW_TRACKING_URI", f"sqlite:///{tmp_path / 'mlflow.db'}")
    experiment = tracking.experiment_name("robot")
    mlflow = tracking.setup(experiment)
    args = (mlflow, experiment, "train", tracking.MODELS_DIGEST_TAG)
    link, run_id = tracking.link_tags(*args, "d1", tracking.SURROGATE_RUN_TAG, "Surrogates")
    assert run_id is None
    assert link == {tracking.MODELS_DIGEST_TAG: "d1", tracking.SURROGATE_RUN_TAG: "unknown"}
    for digest in ("d1", "d1", "d2"):
        with mlflow.start_run(run_name="train", tags={tracking.MODELS_DIGEST_TAG: digest}) as run:
            if digest == "d1":
                latest = run.info.run_id
    link, run_id = tracking.link_tags(*args, "d1", tracking.SURROGATE_RUN_TAG, "Surrogates", ".")
    assert run_id == latest and link[tracking.SURROGATE_RUN_TAG] == latest
    note = link["mlflow.note.content"]
    assert note.startswith(f"Surrogates: run [{latest}](#/experiments/") and note.endswith(").")


@pytest.mark.integration  # a real MLflow SQLite store
def test_the_experiment_is_a_model_training_one_new_or_made_before(tmp_path: Path, monkeypatch):
    """MLflow's UI opens an experiment without the kind on its GenAI overview, not its runs."""
    import mlflow

    monkeypatch.setenv("MLFLOW_TRACKING_URI", f"sqlite:///{tmp_path / 'mlflow.db'}")
    mlflow.set_tracking_uri(f"sqlite:///{tmp_path / 'mlflow.db'}")
    older = mlflow.create_experiment("ftfof-older")  # as an earlier version left it
    assert tracking.KIND_TAG not in mlflow.get_experiment(older).tags
    for name in ("ftfof-new", "ftfof-older"):
        tracking.setup(name)
        tags = mlflow.get_experiment_by_name(name).tags
        assert tags[tracking.KIND_TAG] == "custom_model_development"


def test_every_run_logs_its_settings_the_robot_and_the_seeds(params):
    logged = tracking.run_params(params, polish={"generations": 16, "nested": {"a": 1}})
    assert logged["polish.generations"] == "16" and logged["polish.nested.a"] == "1"
    assert logged["robot"] == params.robot and logged["surface"] == params.surface
    assert logged["base.seed"] == str(params.base.seed)
    assert logged["base.search_seed"] == str(params.search_seed)
