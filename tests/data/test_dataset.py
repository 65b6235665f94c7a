"""Acquisitions -> fixed-length sequences: resampling, split, normalisation, schema."""

import numpy as np
import pyarrow as pa
import pytest

from ftfof import config
from ftfof.data import dataset
from tests.data.fake import fake_acquisition


def test_resampled_velocities_match_the_motion():
    t = np.arange(0.0, 1.2, 1e-3)
    x, z = 0.1 * np.sin(t), 0.02 * t**2
    zero = np.zeros_like(t)
    channels = {"t": t, "x_cmd": x, "z_cmd": z, "Fx_pad": zero, "Fz_pad": zero}
    s = dataset.resample(channels, 1.0, 0.1, 64)
    np.testing.assert_allclose(s["vx"], 0.1 * np.cos(s["t"]), atol=1e-6)
    np.testing.assert_allclose(s["vz"], 0.04 * s["t"], atol=1e-6)


def test_split_is_disjoint_85_15_and_seeded():
    keys = [f"k{i}" for i in range(101)]
    a, b, c = (
        dataset.split(keys, 0.15, 1),
        dataset.split(keys, 0.15, 1),
        dataset.split(keys, 0.15, 2),
    )
    assert a == b and a != c
    assert a.count("validation") == 15 and a.count("train") == 86


@pytest.fixture(scope="module")
def built():
    return dataset.build(fake_acquisition(), config.Dataset(seq_len=64), seed=3, landing_start=0.6)


def test_build_keeps_ok_samples_flags_baselines_and_documents_units(built):
    table, _ = built
    assert table.num_rows == 42  # 40 ok + 2 baselines; the 2 failed are left out
    assert table.schema.field("pull").type == pa.list_(pa.float32(), 64)
    assert table.schema.field("curvature").metadata[b"unit"] == b"1/m"
    assert table.schema.field("vx").metadata[b"unit"] == b"m/s"
    splits = table.column("split").to_pylist()
    sources = table.column("source").to_pylist()
    assert {s for s, src in zip(splits, sources, strict=True) if src.startswith("baseline:")} == {
        "baseline"
    }
    assert splits.count("validation") == 6 and splits.count("train") == 34


def test_normalisation_comes_from_the_training_split_only(built):
    table, norm = built
    x_train, y_train = dataset.arrays(table, "train")
    np.testing.assert_allclose(norm.input_mean, x_train.mean(axis=(0, 1)), rtol=1e-5, atol=1e-6)
    rms = np.sqrt((y_train**2).mean(axis=(0, 1)))
    assert rms[dataset.TARGETS.index("retouch")] == 0  # the fake pads never touch again
    np.testing.assert_allclose(norm.target_scale, np.where(rms > 0, rms, 1.0), rtol=1e-5)
    assert len(norm.target_scale) == len(dataset.TARGETS)
    assert dataset.Normalization.from_json(norm.to_json()) == norm


def test_targets_keep_the_peaks(built):
    table, _ = built
    _, y = dataset.arrays(table, "train")
    rows = table.filter(pa.compute.equal(table.column("split"), "train"))
    fd = dataset.TARGETS.index("Fd")
    np.testing.assert_allclose(
        y[:, :, fd].max(axis=1), rows.column("peak_detachment").to_numpy(), rtol=1e-6
    )


def test_an_acquisition_without_the_film_channels_masks_their_targets():
    """A force log has no film channels and no proof pull: those targets are masked."""
    settings = config.Dataset(seq_len=64)
    table, norm = dataset.build(fake_acquisition(with_film=False), settings, 3, landing_start=0.6)
    _, y = dataset.arrays(table, "train")
    film = [dataset.TARGETS.index(name) for name in ("curvature", "clearance", "holds")]
    assert np.isnan(y[..., film]).all() and np.isfinite(np.delete(y, film, axis=-1)).all()
    assert all(norm.target_scale[k] == 1.0 for k in film)


def test_assembled_tables_carry_their_provenance_and_a_sample_in_two_is_refused():
    import json

    from ftfof.errors import DataError

    acquired = fake_acquisition(n=12, failed=1)
    cfg = config.Dataset(seq_len=32)
    provenance = {"robot": "mst_m3f", "params_hash": "abc"}
    table, summary = dataset.assemble([acquired], cfg, 3, 0.6, provenance)
    alone, norm = dataset.build(acquired, cfg, seed=3, landing_start=0.6)
    assert table.column_names == alone.column_names and table.num_rows == alone.num_rows
    assert table.column("split").to_pylist() == alone.column("split").to_pylist()
    meta = json.loads(table.schema.metadata[dataset.METADATA_KEY])
    assert meta == {
        **provenance,
        "seq_len": 32,
        "hold": cfg.hold,
        "normalization": meta["normalization"],
    }
    assert meta["normalization"] == summary["normalization"] == json.loads(norm.to_json())
    assert summary["samples"] == 14 and summary["excluded_failed"] == 1
    with pytest.raises(DataError, match="sample 'sampled:0' appears twice"):
        dataset.assemble([acquired, acquired.slice(0, 1)], cfg, 3, 0.6, provenance)


def test_the_provenance_hashes_what_the_dataset_is_built_from_and_names_the_simulator(params):
    built = dataset.built_from(7, "r", params.selected_robot.timing, params.dataset)
    versions = {"exudyn": "1.0", "ftfof": "2.0"}
    made = dataset.provenance(built, "glass", {"exudyn": "0.9"}, versions)
    assert made["exudyn"] == "0.9" and made["ftfof"] == "2.0" and made["robot"] == "r"
    assert dataset.provenance(built, "glass", {}, versions)["exudyn"] == "1.0"
    other = dataset.built_from(8, "r", params.selected_robot.timing, params.dataset)
    assert dataset.provenance(other, "glass", {}, versions)["params_hash"] != made["params_hash"]
