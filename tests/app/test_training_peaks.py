"""The train run's peak GPs: fitted where the rows have control values, refitted in refinement with
the hyperparameters they had, and left to the GRU where no row has control values (logs)."""

from __future__ import annotations

import numpy as np
import pyarrow as pa

from ftfof import config
from ftfof.data import dataset
from ftfof.data.acquisition import to_table
from ftfof.pipeline.training import fit_peaks
from ftfof.surrogate.store import TrainingData
from tests.data.fake import fake_acquisition, fake_result


def _data(table: pa.Table) -> TrainingData:
    built, norm = dataset.build(table, config.Dataset(seq_len=32), seed=0, landing_start=0.6)
    return TrainingData(built, norm, 32, config.Dataset().hold, "digest")


def test_peaks_fit_on_the_rows_with_control_values():
    data = _data(fake_acquisition(30, failed=0))
    X = data.decisions("train")
    assert X.shape == (data.inputs("train").shape[0], 12) and np.isfinite(X).all()
    peaks = fit_peaks(data, ["Fp", "body_acc"], {})
    assert sorted(peaks) == ["Fp", "body_acc"]
    truth = data.peaks("train", "body_acc")
    assert np.ptp(truth) > 5.0  # fake pulls of 3..7 N ring the body 3x as hard
    assert np.median(np.abs(peaks["body_acc"](X) - truth)) < 0.1 * np.ptp(truth)


def test_refinement_refits_with_the_hyperparameters_it_had():
    data = _data(fake_acquisition(30, failed=0))
    first = fit_peaks(data, ["body_acc"], {})["body_acc"]
    again = fit_peaks(data, ["body_acc"], {"body_acc": first})["body_acc"]
    np.testing.assert_array_equal(again.length_scale, first.length_scale)
    np.testing.assert_allclose(again(data.decisions("train")), first(data.decisions("train")))


def test_logs_without_control_values_leave_the_peak_to_the_gru():
    results = [fake_result(f"log:{i}", "sampled", i, 3.0 + i % 4) for i in range(20)]
    data = _data(to_table(results, "mst_m3f", "acrylic", {}, 1.0, with_wall_time=False))
    assert fit_peaks(data, ["Fp", "jitter"], {}) == {}
