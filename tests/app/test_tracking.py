"""Run links: a run names the latest finished run that made its inputs, by a digest tag."""

from __future__ import annotations

from pathlib import Path

from ftfof.pipeline import tracking


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
