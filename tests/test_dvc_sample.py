"""`dvc repro` and `dvc exp run` for the sample stage, in a temporary clone (slow)."""

import numpy as np
import pyarrow.parquet as pq
import pytest

from tests.pipeline import clone_to, run

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def repo(tmp_path_factory):
    return clone_to(tmp_path_factory.mktemp("repo"))


def test_repro_samples_1000_mst_m3f_rows_and_then_does_nothing(repo):
    run(repo, "dvc", "repro", "sample")
    table = pq.read_table(repo / "data/trajectories.parquet")
    assert table.num_rows == 1000
    assert set(table.column("robot").to_pylist()) == {"mst_m3f"}
    again = run(repo, "dvc", "repro", "sample")
    assert "didn't change" in again.stdout


def test_exp_run_for_mst_q_samples_vertical_detachment(repo):
    run(repo, "dvc", "exp", "run", "sample", "-S", "robot=mst_q", "-S", "sample.n=200")
    t = pq.read_table(repo / "data/trajectories.parquet").to_pandas()
    assert len(t) == 200
    assert np.all(t[["P3x", "P4x", "P5x"]].to_numpy() == 0.0)
    assert np.all(t["P10x"] == t["P11x"]) and np.all(t["P11x"] == t["P12x"])
