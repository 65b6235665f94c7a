"""Stage `dataset` and `ftfof import-logs`: the Parquet dataset, bad inputs, real-log round trip."""

import json
import os
import subprocess

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from ftfof.data import dataset
from ftfof.data.acquisition import to_table
from ftfof.sim.pool import run_all
from ftfof.trajectory.sampling import sample_feasible
from stages.cli import app
from tests.conftest import dataset_args, write_params
from tests.data.fake import fake_acquisition
from tests.sim.helpers import bench

pytestmark = pytest.mark.integration

runner = CliRunner()
GIT_ENV = {
    **os.environ,
    "GIT_AUTHOR_NAME": "t",
    "GIT_AUTHOR_EMAIL": "t@ftfof.invalid",
    "GIT_COMMITTER_NAME": "t",
    "GIT_COMMITTER_EMAIL": "t@ftfof.invalid",
}


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ds")
    (tmp / "acq").mkdir()
    pq.write_table(fake_acquisition(40, failed=2), tmp / "acq" / "samples.parquet")
    result = runner.invoke(app, dataset_args(tmp, tmp / "acq"))
    assert result.exit_code == 0, result.stderr
    return tmp


def test_the_dataset_has_the_documented_schema_units_and_metadata(built):
    table = pq.read_table(built / "ds" / "samples.parquet")
    seq = json.loads(table.schema.metadata[dataset.METADATA_KEY])["seq_len"]
    assert table.schema.equals(dataset.schema(seq), check_metadata=False)
    units = {f.name: f.metadata[b"unit"].decode() for f in table.schema}
    assert units["x"] == "m" and units["vz"] == "m/s" and units["pull"] == "N" and units["t"] == "s"
    meta = json.loads(table.schema.metadata[dataset.METADATA_KEY])
    assert {"params_hash", "robot", "surface", "exudyn", "ftfof", "normalization"} <= set(meta)
    assert not {k for k in meta if "commit" in k or "run" in k}  # lineage lives in MLflow
    assert meta["robot"] == "mst_m3f" and meta["exudyn"] == "1.13.6"
    summary = json.loads((built / "ds.json").read_text())
    assert summary["excluded_failed"] == 2 and summary["baseline"] == 2
    assert summary["targets_supplied"]["curvature"] == summary["samples"]  # fakes carry the film
    assert (built / "ds.png").stat().st_size > 10_000


def test_the_dataset_bytes_do_not_depend_on_the_git_commit(built, tmp_path, monkeypatch):
    """Two clones at different commits, same acquisition: byte-identical datasets."""
    outputs = []
    for n in range(2):
        repo = tmp_path / f"clone{n}"
        repo.mkdir()
        (repo / "note.txt").write_text(f"commit {n}\n")
        for cmd in (["init", "-q"], ["add", "-A"], ["commit", "-qm", f"c{n}"]):
            subprocess.run(["git", *cmd], cwd=repo, check=True, env=GIT_ENV)
        monkeypatch.setenv("DVC_ROOT", str(repo))
        result = runner.invoke(app, dataset_args(repo, built / "acq"))
        assert result.exit_code == 0, result.stderr
        outputs.append((repo / "ds" / "samples.parquet").read_bytes())
    assert outputs[0] == outputs[1]


def test_train_and_validation_are_disjoint_85_15_and_stable(built, tmp_path):
    table = pq.read_table(built / "ds" / "samples.parquet")
    split = dict(
        zip(table.column("key").to_pylist(), table.column("split").to_pylist(), strict=True)
    )
    train = {k for k, s in split.items() if s == "train"}
    val = {k for k, s in split.items() if s == "validation"}
    assert not train & val
    assert abs(len(val) - 0.15 * (len(train) + len(val))) <= 1
    again = runner.invoke(app, dataset_args(tmp_path, built / "acq"))
    assert again.exit_code == 0
    again_bytes = (tmp_path / "ds" / "samples.parquet").read_bytes()
    assert again_bytes == (built / "ds" / "samples.parquet").read_bytes()  # byte-identical


def test_a_truncated_acquisition_is_one_clear_error_and_leaves_nothing(built, tmp_path):
    (tmp_path / "acq").mkdir()
    good = (built / "acq" / "samples.parquet").read_bytes()
    (tmp_path / "acq" / "samples.parquet").write_bytes(good[: len(good) // 2])
    result = runner.invoke(app, dataset_args(tmp_path, tmp_path / "acq"))
    assert result.exit_code == 1
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "unreadable acquisition" in lines[0]
    assert not (tmp_path / "ds").exists() and not (tmp_path / "ds.json").exists()


def test_a_schema_mismatched_acquisition_names_the_column(built, tmp_path):
    (tmp_path / "acq").mkdir()
    table = pq.read_table(built / "acq" / "samples.parquet")
    pq.write_table(table.drop_columns(["Fp"]), tmp_path / "acq" / "samples.parquet")
    result = runner.invoke(app, dataset_args(tmp_path, tmp_path / "acq"))
    assert result.exit_code == 1
    assert "missing column 'Fp'" in result.stderr
    assert not (tmp_path / "ds").exists()


def test_a_malformed_log_among_good_ones_imports_nothing(tmp_path):
    good = tmp_path / "good.csv"
    bad = tmp_path / "bad.csv"
    t = np.linspace(0, 1, 5)
    pd.DataFrame({"t": t, "x": t, "z": t, "Fz": t}).to_csv(good, index=False)
    pd.DataFrame({"t": t[::-1], "x": t, "z": t, "Fz": t}).to_csv(bad, index=False)
    result = runner.invoke(
        app, ["import-logs", str(good), str(bad), "--out", str(tmp_path / "imp")]
    )
    assert result.exit_code == 1
    assert "bad.csv: row 3, column 't': time does not increase" in result.stderr
    assert not (tmp_path / "imp").exists()


def test_simulated_samples_exported_as_logs_and_imported_back_give_the_same_rows(
    params, m3f, tmp_path
):
    X = sample_feasible(m3f.policy, 5, seed=21).X
    specs = [bench(params).bezier("sampled", i, x) for i, x in enumerate(X)]
    results = run_all(specs, workers=2)
    T3 = m3f.robot.timing.T3
    simulated = to_table(results, "mst_m3f", "acrylic", {}, T3, with_wall_time=False)
    logs = []
    for r in results:  # the documented log format: t [s], x and z [mm], Fz and Fx [N], proof
        c = r.channels
        keep = c["t"] >= 0
        path = tmp_path / f"run{r.sample_id}.csv"
        step = pd.DataFrame(
            {
                "t": c["t"][keep],
                "x": c["x_cmd"][keep] * 1e3,
                "z": c["z_cmd"][keep] * 1e3,
                "Fz": c["Fz_pad"][keep],  # a log holds the foot force
                "Fx": c["Fx_pad"][keep],
                "proof": 0,
            }
        )
        pd.concat([step, _proof_rows(step, r.scalars)]).to_csv(
            path, index=False, float_format="%.9g"
        )
        logs.append(str(path))
    result = runner.invoke(app, ["import-logs", *logs, "--out", str(tmp_path / "imp")])
    assert result.exit_code == 0, result.stderr
    imp = pa.concat_tables([pq.read_table(p) for p in sorted((tmp_path / "imp").glob("*.parquet"))])
    # the logged pull's verdict is the simulated one, and every imported log supplies `holds`
    for name in ("proof_held", "held_pull"):
        np.testing.assert_allclose(
            imp.column(name).to_numpy(), simulated.column(name).to_numpy(), rtol=1e-6, err_msg=name
        )
    assert (
        dataset.summarize(dataset.build(imp, params.dataset, seed=0)[0], 5, 64)[
            "imported_with_proof"
        ]
        == 5
    )
    settings = params.dataset
    a, _ = dataset.build(simulated, settings, seed=0)
    b, _ = dataset.build(imp, settings, seed=0)

    def series(table, name):
        return np.stack(table.column(name).to_numpy(zero_copy_only=False))

    for name in ("x", "z", "vx", "vz"):
        sa, sb = series(a, name), series(b, name)
        np.testing.assert_allclose(sb, sa, atol=1e-4 * np.abs(sa).max(), err_msg=name)

    # A log has no switch: its windows end where the pull falls below 5 % of its peak, not at
    # the switch, so the series differ at the window edges; the peaks the objectives read agree
    # for a pad that lets go. One that bonds again before the switch (a sample here drags its
    # re-bonded pad to a 16 N pull at 0.6 s) has its detachment window run on to the switch,
    # which a log cannot see.
    def lets_go(r) -> bool:
        """No bond forms again between the trajectory's start and the switch."""
        t, bonds = r.channels["t"], r.channels["bonds"]
        return bool(np.all(np.diff(bonds[(t >= 0) & (t <= r.scalars["switch_time"])]) <= 0))

    let_go = np.array([lets_go(r) for r in results])
    assert let_go.sum() >= 3
    for name in ("pull", "Fd", "Fp"):
        sa, sb = series(a, name).max(axis=1), series(b, name).max(axis=1)
        np.testing.assert_allclose(sb[let_go], sa[let_go], rtol=1e-3, atol=1e-3, err_msg=name)
    for name in ("body_acc", "curvature"):  # no IMU and no film channel in a force log
        assert np.isnan(series(b, name)).all(), name


def _proof_rows(step: pd.DataFrame, scalars: dict) -> pd.DataFrame:
    """What the platform's sensor logs in a simulated sample's proof pull, from its figures: a
    ramp to the pull it bore over 0.2 s, then F_proof held for 0.5 s where it held, or the load
    falling away where a tenth of the pad let go."""
    t0 = float(step.t.iloc[-1])
    ramp = np.linspace(0.0, scalars["held_pull"], 21)[1:]
    after = np.full(50, scalars["held_pull"] if scalars["proof_held"] == 1.0 else 0.1)
    pull = np.concatenate([ramp, after])
    t = t0 + 0.01 * np.arange(1, pull.size + 1)
    last = step.iloc[-1]
    return pd.DataFrame({"t": t, "x": last.x, "z": last.z, "Fz": pull, "Fx": 0.0, "proof": 1})


def test_a_later_stage_s_settings_leave_the_dataset_bytes_unchanged(built, raw_params, tmp_path):
    """The metadata hashes the params the dataset is built from, not every stage's."""
    data = {**raw_params, "polish": {**raw_params["polish"], "generations": 3}}
    data["evaluate"] = {**raw_params["evaluate"], "front_points": 2}
    params = write_params(tmp_path / "params.yaml", data)
    result = runner.invoke(app, dataset_args(tmp_path, built / "acq", params=params))
    assert result.exit_code == 0, result.stderr
    original = (built / "ds" / "samples.parquet").read_bytes()
    assert (tmp_path / "ds" / "samples.parquet").read_bytes() == original
    data["dataset"] = {**raw_params["dataset"], "validation_fraction": 0.3}
    params = write_params(tmp_path / "split.yaml", data)
    result = runner.invoke(app, dataset_args(tmp_path / "s", built / "acq", params=params))
    assert result.exit_code == 0, result.stderr
    assert (tmp_path / "s" / "ds" / "samples.parquet").read_bytes() != original
