"""A refinement round's decisions, without files or tracking: the stop rule (fidelity on the first
priority *and* a front the simulator passes), the nominees, what a round carries to the next."""

from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from ftfof.config import Optimize, Refine, RefineTarget, Train
from ftfof.errors import SimulationError
from ftfof.evaluate.fidelity import fidelity
from ftfof.evaluate.runs import OPTIMUM
from ftfof.optimize.select import rhs_ranking
from ftfof.refine.rounds import (
    ACQUIRED,
    Measured,
    Round,
    Rounds,
    Verdict,
    acquired_points,
    fine_tuning,
    nominees_of,
    nothing_new,
    record,
    refused_rows,
    round_target_met,
    successful,
)
from ftfof.trajectory.bezier import DECISION_NAMES

S = np.array([[1.0], [2.0], [3.0], [4.0], [5.0]])
RANKED = fidelity(["fs1"], S * 1.01, S)[0]  # rho 1, 1 % off
TARGET = RefineTarget(spearman=0.9, relative_error=0.15, clean=0.9)


def test_fidelity_and_a_clean_front_stop_the_refinement():
    assert round_target_met(TARGET, RANKED, 0.01, clean=0.95)


def test_a_front_of_exploits_refines_on_even_when_fs1_ranks_well():
    assert not round_target_met(TARGET, RANKED, 0.01, clean=0.5)


def test_a_clean_front_ranked_badly_refines_on():
    reversed_ranks = fidelity(["fs1"], S[::-1], S)[0]
    assert not round_target_met(TARGET, reversed_ranks, 0.01, clean=1.0)
    assert not round_target_met(TARGET, RANKED, 0.5, clean=1.0)  # the optimum itself far off


def test_nominees_are_the_pools_pull_jitter_layers_in_rhs_order():
    cfg = Optimize()
    X1, F1 = np.arange(36.0).reshape(3, 12), np.array([[7.0, 9.0], [6.5, 4.0], [7.2, 3.0]])
    # round 2 simulated round 1's second point again (its optimum), and a better one
    X2, F2 = np.vstack([X1[1], X1[0] + 100]), np.array([[6.0, 3.0], [6.4, 3.5]])
    measured = [Measured(X1, F1, "refine:1"), Measured(X2, F2, "refine:2")]
    chosen = nominees_of(measured, 3, cfg)
    # the repeat counts once, with round 1's values (its 6.0 / 3.0 would have dominated all);
    # then the front of (6.4, 3.5) and (7.2, 3.0) in RHS order, then (6.5, 4.0), which (6.4, 3.5)
    # dominates although RHS over the whole pool would take it second
    np.testing.assert_array_equal(chosen.X, np.vstack([X2[1], X1[2], X1[1]]))
    assert chosen.origin == ["refine:2", "refine:1", "refine:1"]
    pool = np.vstack([F1, F2[1:]])
    assert rhs_ranking(pool, np.arange(4), cfg, 2) == [3, 1]  # what the layers prevent
    assert len(nominees_of(measured, 9, cfg).X) == 4
    assert nominees_of(measured, 0, cfg) is None
    # a trajectory the check refused (to the nanometre) is not nominated again, nor one with an
    # objective the simulation could not give
    refused = nominees_of(measured, 9, cfg, X2[1:] + 1e-10)
    np.testing.assert_array_equal(refused.X, np.vstack([X1[1], X1[2], X1[0]]))
    unknown = [Measured(X1, np.where(np.arange(3)[:, None] == 2, np.nan, F1), "refine:1")]
    np.testing.assert_array_equal(nominees_of(unknown, 9, cfg).X, X1[[1, 0]])
    assert nominees_of([Measured(np.empty((0, 12)), np.empty((0, 2)), "refine:1")], 3, cfg) is None


# five rows of the default robot's paper-scale acquisition on the grip foot, as the simulator wrote
# them: sampled:1
# and sampled:156 clean, sampled:0 bent its film to 4.9 mm, sampled:105 shook the body to 2.9 m/s²
# (within the plate foot's limit),
# then the polynomial baseline (clean, but no decision row)
ACQUIRED_ROWS = Path(__file__).parents[1] / "data" / "acquired_rows.parquet"


def _proof_pulled(table: pa.Table, let_go: str | None = None) -> pa.Table:
    """The rows (from before the proof pull) with its verdict: each held F_proof, but ``let_go``,
    which let a tenth of its pad go at 5 N."""
    keys = table.column("key").to_pylist()
    force = 6.58922
    held = [0.0 if k == let_go else 1.0 for k in keys]
    pulls = [5.0 if k == let_go else force for k in keys]
    table = table.append_column("proof_pull", pa.array([force] * len(keys)))
    return table.append_column("held_pull", pa.array(pulls)).append_column(
        "proof_held", pa.array(held)
    )


def test_the_acquisitions_clean_sampled_runs_are_candidates_with_their_objectives(m3f, params):
    table = _proof_pulled(pq.read_table(ACQUIRED_ROWS))
    points = acquired_points(m3f, table, params.dataset)
    assert points.origin == ACQUIRED
    keys = table.column("key").to_pylist()
    X = table.to_pandas()[list(DECISION_NAMES)].to_numpy(float)
    # sampled:105's 2.9 m/s2 is within the plate foot's body limit (6.1 m/s2, 1.2x its
    # polynomial's), so it is a candidate now; sampled:0's bent film is not
    clean = [keys.index(k) for k in ("sampled:1", "sampled:156", "sampled:105")]
    np.testing.assert_array_equal(points.X, X[clean])
    # the simulated pull and jitter, the objectives the check would measure (reference values)
    np.testing.assert_allclose(
        points.F[:, :2], [[6.968, 1.353], [7.441, 2.140], [8.131, 4.467]], atol=2e-3
    )
    # a failed run is no candidate either, whatever its channels say
    failed = table.set_column(
        table.schema.get_field_index("status"),
        "status",
        pa.array(["failed" if k == "sampled:1" else "ok" for k in keys]),
    )
    np.testing.assert_array_equal(acquired_points(m3f, failed, params.dataset).X, points.X[1:])
    # and one whose landed pad let go in the proof pull is none
    let_go = _proof_pulled(pq.read_table(ACQUIRED_ROWS), let_go="sampled:156")
    np.testing.assert_array_equal(acquired_points(m3f, let_go, params.dataset).X, points.X[[0, 2]])
    # they lead the pool: sampled:1 is a better trade than a round's point it dominates
    round_1 = Measured(X[[0]] + 1e-3, np.array([[7.1, 1.5, 0, 0, 0, 0]]), "refine:1")
    chosen = nominees_of([points, round_1], 1, Optimize())
    assert chosen.origin == [ACQUIRED] and np.array_equal(chosen.X, points.X[:1])


def _table(X: np.ndarray, status: list[str], source: list[str] | None = None) -> pa.Table:
    columns = {n: X[:, i] for i, n in enumerate(DECISION_NAMES)}
    source = source or ["front"] * len(X)
    return pa.table({**columns, "status": status, "source": source, "error": [""] * len(X)})


def test_a_round_carries_its_points_its_refusals_and_its_rows_to_the_next():
    X = np.arange(36.0).reshape(3, 12)
    rounds = Rounds()
    base = _table(X[:1], ["ok"])
    round_1 = _table(X, ["ok", "ok", "failed"])
    new = rounds.unseen(round_1, base)  # the training data holds the first trajectory
    np.testing.assert_array_equal(new.column("P3x").to_numpy(), X[1:, 0])
    rounds.measure(Measured(X[1:], np.array([[6.0, 3.0], [6.5, 2.0]]), "refine:1"))
    chosen = rounds.nominees(5, Optimize())
    assert chosen is not None and len(chosen.X) == 2  # both clean points, before the search
    rounds.close(X[1:2] + 1e-10, new)  # the search's check refused the second trajectory
    again = rounds.nominees(5, Optimize())
    np.testing.assert_array_equal(again.X, X[2:])  # never nominated again
    assert rounds.unseen(round_1, base).num_rows == 0  # every trajectory is known now
    assert not nothing_new(new) and nothing_new(new.filter(pa.array([False, True])))


def test_a_round_whose_optimum_failed_is_one_clear_error():
    X = np.zeros((2, 12))
    ok = successful(_table(X, ["ok", "ok"], [OPTIMUM, "front"]))
    assert len(ok) == 2
    with pytest.raises(SimulationError, match="re-simulation failed"):
        successful(_table(X, ["failed", "ok"], [OPTIMUM, "front"]))


def test_fine_tuning_trains_the_used_model_with_the_rounds_settings():
    tune = fine_tuning(Train(use="mse"), Refine(epochs=5, patience=2, lr=3e-4))
    assert (tune.losses, tune.epochs, tune.patience, tune.lr) == (["mse"], 5, 2, 3e-4)


def test_a_rounds_record_names_each_objective_and_rounds_its_numbers():
    fid = fidelity(["fs1", "fsj"], S.repeat(2, axis=1) * 1.01, S.repeat(2, axis=1))
    verdict = Verdict(fid, np.array([[6.123456789, 1.0]]), np.array([[6.0, 1.2]]), 0.8, False)
    entry = record(2, 17, verdict, ["fs1", "fsj"])
    assert entry["round"] == 2 and entry["added"] == 17 and entry["clean_fraction"] == 0.8
    assert entry["optimum"]["predicted"] == {"fs1": 6.123457, "fsj": 1.0}
    assert set(entry["fidelity"]) == {"fs1", "fsj"}
    assert entry["fidelity"]["fs1"]["spearman"] == pytest.approx(1.0)


def _round(**changes) -> Round:
    record = {
        "round": 2,
        "added": 31,
        "clean_fraction": 0.84,
        "fidelity": {"fs1": {"spearman": 0.91234, "median_relative_error": 0.0456}},
        "optimum": {"predicted": {"fs1": 6.94321}, "simulated": {"fs1": 7.0123}},
    }
    return Round(record, **{"target_met": False, "simulated": 50, "seconds": 12.34, **changes})


def test_a_round_in_one_line_says_how_it_ended():
    line = _round().line("fs1")
    assert line == (
        "round 2: 50 simulated now; fs1 rho 0.912, median relative error 4.6 %, optimum 6.943 "
        "predicted vs 7.012 simulated; 84 % clean; 31 added; 12.3 s"
    )
    assert not _round().last
    met, known = _round(target_met=True), _round(nothing_new=True)
    assert met.last and "; target met, stop; " in met.line("fs1")
    assert known.last and "; nothing new to learn from, stop; " in known.line("fs1")


def test_the_rows_an_optimums_check_refused():
    import pandas as pd

    from ftfof.evaluate.run import Inputs

    front = pd.DataFrame(
        np.arange(3 * len(DECISION_NAMES), dtype=float).reshape(3, -1),
        columns=list(DECISION_NAMES),
        index=pd.Index([4, 7, 9], name="row"),
    )
    checks = [{"row": 7, "ok": False}, {"row": 4, "ok": True}, {"row": 9, "ok": False}]
    inputs = Inputs({"simulator_check": checks}, front, ["fs1"], "d")
    np.testing.assert_array_equal(refused_rows(inputs), front.loc[[7, 9]].to_numpy())
    none = Inputs({"simulator_check": checks[1:2]}, front, ["fs1"], "d")
    assert refused_rows(none).shape == (0, len(DECISION_NAMES))


def test_the_grown_data_holds_every_rounds_rows_and_is_named_by_round():
    from ftfof import config
    from ftfof.data import dataset
    from ftfof.data.refinement import round_rows
    from ftfof.digests import json_sha256
    from ftfof.refine.rounds import grown
    from ftfof.surrogate.store import TrainingData
    from tests.data.fake import fake_acquisition

    built, norm = dataset.build(fake_acquisition(n=8, failed=0), config.Dataset(seq_len=16), 3)
    data = TrainingData(built, norm, 16, 0.1, "d0")
    sampled = built.filter(pa.compute.equal(built.column("source"), "sampled"))
    first, second = round_rows(sampled.slice(0, 3), 1), round_rows(sampled.slice(3, 2), 2)
    out = grown(data, Rounds(added=[first]), second, "key", 2)
    assert out.table.num_rows == built.num_rows + 5
    assert out.table.column("key").to_pylist()[-2:] == ["refine:2:3", "refine:2:4"]
    assert (out.normalization, out.seq_len, out.hold) == (norm, 16, 0.1)
    assert out.metadata_digest == json_sha256({"dataset": "d0", "refine": "key", "round": 2}, 16)
