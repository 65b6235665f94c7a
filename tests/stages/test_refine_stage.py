"""Stage `refine`: rounds append re-simulated front rows (split like the dataset) to the data,
fine-tune and search again; a killed round resumes without losing or re-simulating samples."""

import copy
import json

import mlflow
import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from ftfof.digests import file_sha256, models_digest
from ftfof.pipeline.jobs import Acquisition
from ftfof.refine import rounds
from ftfof.surrogate import fit
from ftfof.surrogate.store import weights_file
from ftfof.trajectory.bezier import DECISION_NAMES, same_trajectory
from stages.cli import app
from tests.conftest import optimize_args, refine_args, tree_bytes, write_params
from tests.stages.conftest import TINY_OPTIMIZE

pytestmark = pytest.mark.integration

runner = CliRunner()
# A target no surrogate meets: every round runs.
UNREACHABLE = {"spearman": 1.0, "relative_error": 1e-12, "clean": 1.0}
REFINE = {"rounds": 2, "points": 3, "epochs": 2, "patience": 1, "generations": 3}


@pytest.fixture(scope="module", autouse=True)
def _near_front_from_round_one():
    """A tiny round adds about three training rows: let them have a local landing GP, so the
    rounds, and a resumed run's rebuild of them, go through NearFront as at paper scale."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(fit, "MIN_NEAR_FRONT_ROWS", 2)
        yield


@pytest.fixture(scope="module")
def optimized(trained, tmp_path_factory):
    """The shared tiny dataset and models, optimised; simulations one at a time, one per part."""
    tmp, uri, data = trained
    data = copy.deepcopy(data)
    data["optimize"] = {**data["optimize"], **TINY_OPTIMIZE}
    data["acquire"] = {**data["acquire"], "workers": 1, "batch": 1}
    data["refine"] = {**data["refine"], **REFINE, "target": UNREACHABLE}
    work = tmp_path_factory.mktemp("refine")
    params = write_params(work / "params.yaml", data)
    args = optimize_args(params, tmp / "models", work, work)
    result = runner.invoke(app, args, env={"MLFLOW_TRACKING_URI": uri})
    assert result.exit_code == 0, result.output
    return tmp, work, uri, data


def _refine(optimized, name: str, **refine):
    tmp, work, uri, data = optimized
    data = copy.deepcopy(data)
    data["refine"] = {**data["refine"], **refine}
    params = write_params(work / f"{name}.yaml", data)
    args = refine_args(params, tmp, work / "optimize", work / name, work / f"{name}.png")
    return runner.invoke(app, args, env={"MLFLOW_TRACKING_URI": uri}), work / name


@pytest.fixture(scope="module")
def refined(optimized):
    result, out = _refine(optimized, "two_rounds")
    assert result.exit_code == 0, result.output
    return out


def test_two_rounds_append_rows_with_their_source_and_hold_some_out(optimized, refined):
    tmp, work, _, _ = optimized
    report = json.loads((work / "two_rounds.json").read_text())
    assert [r["round"] for r in report["rounds"]] == [1, 2]
    assert report["seconds"] >= sum(r["seconds"] for r in report["rounds"]) > 0
    for r in report["rounds"]:
        assert set(r) == {"round", "added", "clean_fraction", "fidelity", "optimum", "seconds"}
        assert 0.0 <= r["clean_fraction"] <= 1.0
        optimum = r["optimum"]
        assert set(r["fidelity"]) == set(optimum["predicted"]) == set(optimum["simulated"])
        for values in r["fidelity"].values():
            assert set(values) == {"mae", "median_relative_error", "spearman"}
    original = pq.read_table(tmp / "ds" / "samples.parquet")
    grown = pq.read_table(refined / "dataset" / "samples.parquet")
    before = grown.slice(0, original.num_rows).to_pandas()
    pd.testing.assert_frame_equal(before, original.to_pandas())  # nothing before is touched
    assert grown.schema.metadata == original.schema.metadata  # the same normalisation
    added = grown.slice(original.num_rows).to_pandas()
    names = list(DECISION_NAMES)
    seen = original.to_pandas()[names].to_numpy(float)
    for r in report["rounds"]:
        rows = added[added.source == f"refine:{r['round']}"]
        sims = pq.read_table(refined / f"round-{r['round']}" / "simulations" / "samples.parquet")
        ok = sims.to_pandas().query("status == 'ok'")[names].to_numpy(float)
        # every successful simulation whose trajectory the data does not hold yet (a nominee
        # optimum, or a front member the warm-started search kept from an earlier round, does)
        new = ~same_trajectory(ok, seen)
        assert len(rows) == r["added"] == new.sum() >= 1
        seen = np.vstack([seen, ok[new]])
        assert all(k.startswith(f"refine:{r['round']}:") for k in rows.key)
        held_out = round(0.15 * r["added"])  # the dataset's validation_fraction: 1 of 4
        assert list(rows.split).count("validation") == held_out
        assert "train" in set(rows.split)
    assert len(added) == sum(r["added"] for r in report["rounds"])
    assert "validation" in set(added.split)  # early stopping sees where the optimiser went


def test_final_models_and_optimum_are_the_last_rounds(optimized, refined):
    tmp, *_ = optimized
    assert tree_bytes(refined / "models") == tree_bytes(refined / "round-2" / "models")
    assert tree_bytes(refined / "optimize") == tree_bytes(refined / "round-2" / "optimize")
    optimum = json.loads((refined / "optimize" / "optimum.json").read_text())
    assert optimum["models_digest"] == models_digest(refined / "models")
    assert models_digest(refined / "models") != models_digest(tmp / "models")  # fine-tuned
    # each round's landing GP gets a local part on the rounds' training rows so far
    local = [
        json.loads((refined / f"round-{k}" / "models" / "peaks.json").read_text())["Fp"]["local"]
        for k in (1, 2)
    ]
    assert 0 < len(local[0]["train_inputs"]) < len(local[1]["train_inputs"])
    # round 2 re-simulated round 1's optimum
    first = json.loads((refined / "round-1" / "optimize" / "optimum.json").read_text())
    sims = pq.read_table(refined / "round-2" / "simulations" / "samples.parquet").to_pandas()
    assert sims[sims.source == "optimum"].sample_id.tolist() == [first["front_row"]]


def test_the_rounds_clean_points_join_the_simulator_check(optimized, refined):
    second = pq.read_table(refined / "round-2" / "optimize" / "front.parquet").to_pandas()
    nominated = second[second.origin != "front"]
    assert set(nominated.origin) <= {"acquire", "refine:1", "refine:2"}
    assert (second.origin == "front").iloc[: len(second) - len(nominated)].all()  # after the front
    checked = json.loads((refined / "round-2" / "optimize" / "optimum.json").read_text())
    rows = {v["row"] for v in checked["simulator_check"]}
    assert nominated.recheck_feasible.any()
    assert set(nominated.row[nominated.recheck_feasible]) <= rows  # every one simulated again
    # the round's decision rows are the simulations' own: a nominee is a point simulated before
    sims = pd.concat(
        pq.read_table(refined / f"round-{k}" / "simulations" / "samples.parquet").to_pandas()
        for k in (1, 2)
    )
    simulated = {tuple(r) for r in sims[list(DECISION_NAMES)].to_numpy()}
    assert all(tuple(r) in simulated for r in nominated[list(DECISION_NAMES)].to_numpy())
    assert len(nominated) >= 1


def test_mlflow_parent_run_with_a_linked_child_per_round(optimized, refined):
    _, _, uri, _ = optimized
    client = mlflow.MlflowClient(tracking_uri=uri)
    experiment = client.get_experiment_by_name("ftfof-mst_m3f").experiment_id
    parent = client.search_runs([experiment], "attributes.run_name = 'refine'")[0]
    children = client.search_runs(
        [experiment], f"tags.`mlflow.parentRunId` = '{parent.info.run_id}'"
    )
    by_name = {c.info.run_name: c for c in children}
    assert set(by_name) == {"refine-1", "refine-2"}
    first, second = by_name["refine-1"], by_name["refine-2"]
    assert client.get_run(first.data.tags["ftfof.surrogate_run"]).info.run_name == "train"
    assert client.get_run(first.data.tags["ftfof.optimize_run"]).info.run_name == "optimize"
    assert second.data.tags["ftfof.surrogate_run"] == first.info.run_id
    assert second.data.tags["ftfof.optimize_run"] == first.info.run_id
    assert "fidelity.fs1.mae" in second.data.metrics and "refine.added" in second.data.metrics
    # each round's run spans the round (opened when it started), the parent every round
    report = json.loads((refined.parent / "two_rounds.json").read_text())
    for child, record in zip((first, second), report["rounds"], strict=True):
        assert child.info.end_time - child.info.start_time >= 1000 * record["seconds"] - 10
    assert parent.info.end_time - parent.info.start_time >= 1000 * sum(
        r["seconds"] for r in report["rounds"]
    )
    # the fine-tuned models are a registered version, named by the parent run
    use = optimized[3]["train"]["use"]
    uri = parent.data.tags["ftfof.model"]
    name, version = uri.removeprefix("models:/").split("/")
    registered = client.get_model_version(name, version)
    assert name == f"ftfof-mst_m3f-{use}" and registered.run_id == parent.info.run_id
    weights = file_sha256(refined / "models" / weights_file(use))
    assert registered.tags["ftfof.weights_sha256"] == weights
    assert client.list_artifacts(second.info.run_id, "models")
    # every run says what produced it: its settings and the seeds, each round its number
    seed = str(optimized[3]["base"]["seed"])
    assert parent.data.params["base.seed"] == seed and "refine.rounds" in parent.data.params
    assert second.data.params["base.seed"] == seed and second.data.params["round"] == "2"


class KilledError(Exception):
    """The process dying right after a part reached the disk."""


def test_a_killed_round_resumes_without_losing_or_resimulating(optimized, refined, monkeypatch):
    written = []
    original = Acquisition._write_part

    def killed_after_first_part(self, results):
        original(self, results)
        written.append(len(results))
        raise KilledError

    monkeypatch.setattr(Acquisition, "_write_part", killed_after_first_part)
    result, out = _refine(optimized, "resumed")
    assert isinstance(result.exception, KilledError) and written == [1]
    assert len(list((out / "round-1" / "simulations" / "pending").glob("part-*"))) == 1
    assert not (out / "round-1" / "round.json").exists()

    def counted(self, results):
        original(self, results)
        written.append(len(results))

    monkeypatch.setattr(Acquisition, "_write_part", counted)
    result, out = _refine(optimized, "resumed")
    assert result.exit_code == 0, result.output
    per_round = [
        pq.read_table(refined / f"round-{k}" / "simulations" / "samples.parquet").num_rows
        for k in (1, 2)
    ]
    assert sum(written[1:]) == sum(per_round) - 1  # the killed part was not simulated again
    assert tree_bytes(out) == tree_bytes(refined)  # every sample, model and front as uninterrupted


def test_a_run_killed_in_round_two_rebuilds_round_one_as_it_was(optimized, refined, monkeypatch):
    original = Acquisition._write_part

    def killed_in_round_two(self, results):
        original(self, results)
        if "round-2" in self.out.as_posix():
            raise KilledError

    monkeypatch.setattr(Acquisition, "_write_part", killed_in_round_two)
    result, out = _refine(optimized, "resumed_late")
    assert isinstance(result.exception, KilledError)
    assert (out / "round-1" / "round.json").exists()
    assert not (out / "round-2" / "round.json").exists()
    monkeypatch.setattr(Acquisition, "_write_part", original)
    result, out = _refine(optimized, "resumed_late")
    assert result.exit_code == 0, result.output
    # round 2's nominees, refusals and training rows come from round 1's files on disk
    assert tree_bytes(out) == tree_bytes(refined)


def test_a_met_target_stops_before_training(optimized):
    tmp, work, _, _ = optimized
    met = {"spearman": -1.0, "relative_error": 1e9, "clean": 0.0}
    result, out = _refine(optimized, "met", target=met)
    assert result.exit_code == 0, result.output
    (only,) = json.loads((work / "met.json").read_text())["rounds"]
    assert only["added"] == 0 and not (out / "round-1" / "models").exists()
    assert tree_bytes(out / "optimize") == tree_bytes(work / "optimize")
    assert tree_bytes(out / "models") == tree_bytes(tmp / "models")


def test_a_round_with_nothing_new_to_learn_from_ends_the_rounds(optimized, monkeypatch):
    """Every point already in the training data (a front of known trajectories): the first round
    keeps the models and optimum it started from, and the second never runs."""
    tmp, work, _, _ = optimized
    monkeypatch.setattr(rounds, "unseen", lambda rows, tables: rows.slice(0, 0))
    result, out = _refine(optimized, "known")
    assert result.exit_code == 0, result.output
    assert "nothing new to learn from, stop" in result.output
    (only,) = json.loads((work / "known.json").read_text())["rounds"]
    assert only["added"] == 0 and not (out / "round-1" / "models").exists()
    assert json.loads((out / "round-1" / "round.json").read_text())["nothing_new"]
    assert tree_bytes(out / "optimize") == tree_bytes(work / "optimize")
    assert tree_bytes(out / "models") == tree_bytes(tmp / "models")
    assert tree_bytes(out / "dataset") == tree_bytes(tmp / "ds")


def test_zero_rounds_pass_the_optimize_outputs_on(optimized):
    tmp, work, _, _ = optimized
    result, out = _refine(optimized, "none", rounds=0)
    assert result.exit_code == 0, result.output
    assert json.loads((work / "none.json").read_text())["rounds"] == []
    assert tree_bytes(out / "optimize") == tree_bytes(work / "optimize")
    assert tree_bytes(out / "models") == tree_bytes(tmp / "models")
    assert tree_bytes(out / "dataset") == tree_bytes(tmp / "ds")
