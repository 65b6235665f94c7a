"""The peak GPs of :mod:`ftfof.surrogate.fit`: fitted where the rows have control values, refitted
in refinement with the hyperparameters they had, and left to the GRU where no row has control
values (logs)."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pytest

from ftfof import config
from ftfof.data import dataset, refinement
from ftfof.data.acquisition import to_table
from ftfof.surrogate import fit
from ftfof.surrogate.fit import fit_peaks
from ftfof.surrogate.peaks import NearFront, PeakModel
from ftfof.surrogate.store import TrainingData
from tests.data.fake import fake_acquisition, fake_result


def _data(table: pa.Table) -> TrainingData:
    built, norm = dataset.build(table, config.Dataset(seq_len=32), seed=0, landing_start=0.6)
    return TrainingData(built, norm, 32, config.Dataset().hold, "digest")


@pytest.fixture(scope="module")
def data() -> TrainingData:
    return _data(fake_acquisition(80, failed=0))


def test_peaks_fit_on_the_training_rows_and_predict_the_validation_rows(data):
    """The fakes ring the body 3x their pull, which the first control value sets."""
    peaks = fit_peaks(data, ["Fp", "body_acc"], {})
    assert sorted(peaks) == ["Fp", "body_acc"]
    X, truth = data.decisions("validation"), data.peaks("validation", "body_acc")
    assert X.shape == (len(truth), 12) and np.isfinite(X).all() and np.ptp(truth) > 5.0
    assert np.abs(peaks["body_acc"](X) - truth).max() < 0.05 * np.ptp(truth)
    ell = peaks["body_acc"].length_scale
    assert ell[0] < 0.1 * ell[1:].min()  # ARD found the control value that matters


def test_refinement_refits_on_the_grown_rows_with_the_hyperparameters_it_had(data, monkeypatch):
    first = fit_peaks(_data(fake_acquisition(30, failed=0)), ["body_acc"], {})["body_acc"]

    def no_new_fit(*args, **kwargs):
        raise AssertionError("a refit must not search the hyperparameters again")

    monkeypatch.setattr(fit, "fit_peak_model", no_new_fit)
    again = fit_peaks(data, ["body_acc"], {"body_acc": first})["body_acc"]
    np.testing.assert_array_equal(again.length_scale, first.length_scale)
    assert again.train_inputs.shape == (len(data.peaks("train", "body_acc")), 12)
    X, truth = data.decisions("train"), data.peaks("train", "body_acc")
    assert np.abs(again(X) - truth).max() < np.abs(first(X) - truth).max()


def test_logs_without_control_values_leave_the_peak_to_the_gru():
    results = [fake_result(f"log:{i}", "sampled", i, 3.0 + i % 4) for i in range(20)]
    data = _data(to_table(results, "mst_m3f", "acrylic", {}, 1.0, with_wall_time=False))
    assert fit_peaks(data, ["Fp", "jitter"], {}) == {}


def _from_rounds(data: TrainingData, n: int) -> TrainingData:
    """``data`` with its first ``n`` rows relabelled as a refinement round's."""
    table = data.table
    sources = table.column("source").to_pylist()
    sources[:n] = [refinement.source(1)] * n
    index = table.schema.get_field_index("source")
    relabelled = table.set_column(index, table.schema.field(index), pa.array(sources))
    return TrainingData(relabelled, data.normalization, data.seq_len, data.hold, "digest")


def test_refinement_adds_a_local_gp_on_the_rounds_rows_for_the_near_front_peaks(data):
    first = fit_peaks(data, ["Fp", "body_acc"], {})
    rounds = _from_rounds(data, 40)
    near = rounds.from_rounds("train")
    assert near.sum() >= fit.MIN_NEAR_FRONT_ROWS and not near.all()
    again = fit_peaks(rounds, ["Fp", "body_acc"], first, near_front_peaks=["body_acc"])
    assert isinstance(again["body_acc"], NearFront) and isinstance(again["Fp"], PeakModel)
    local = again["body_acc"].local
    assert local.train_inputs.shape == (near.sum(), 12)  # the rounds' training rows alone
    np.testing.assert_array_equal(
        again["body_acc"].broad.length_scale, first["body_acc"].length_scale
    )
    # the next round refits the broad GP inside it, and fits a new local one
    third = fit_peaks(rounds, ["body_acc"], again, near_front_peaks=["body_acc"])["body_acc"]
    np.testing.assert_array_equal(third.broad.length_scale, first["body_acc"].length_scale)
    few = _from_rounds(data, fit.MIN_NEAR_FRONT_ROWS // 2)
    alone = fit_peaks(few, ["body_acc"], first, near_front_peaks=["body_acc"])["body_acc"]
    assert isinstance(alone, PeakModel)  # too few rounds' rows for a local GP yet


def test_a_near_front_target_without_a_broad_gp_gets_the_local_gp_alone(data):
    """train.peaks without body_acc: the rounds' rows still give it a local GP (blended with the
    GRU's maximum in prediction), and until there are enough of them it gets no model at all."""
    first = fit_peaks(data, ["Fp"], {})
    rounds = _from_rounds(data, 40)
    again = fit_peaks(rounds, ["Fp"], first, near_front_peaks=["Fp", "body_acc"])
    body = again["body_acc"]
    assert isinstance(body, NearFront) and body.broad is None
    assert body.local.train_inputs.shape == (rounds.from_rounds("train").sum(), 12)
    assert isinstance(again["Fp"], NearFront) and again["Fp"].broad is not None
    few = _from_rounds(data, fit.MIN_NEAR_FRONT_ROWS // 2)
    assert "body_acc" not in fit_peaks(few, ["Fp"], first, near_front_peaks=["body_acc"])
