"""Physical-platform logs: units, signs, and errors that name file, row and column."""

import numpy as np
import pandas as pd
import pytest

from ftfof import config
from ftfof.data.logs import parse
from ftfof.errors import DataError

FMT = config.Logs()


def _log(**overrides):
    t = np.linspace(0, 1.1, 12)
    df = pd.DataFrame(
        {"t": t, "x": 120 * t, "z": 30 * np.sin(np.pi * t), "Fz": np.linspace(-5, 5, 12), "Fx": 0.1}
    )
    for k, v in overrides.items():
        df[k] = v
    return df


def test_a_log_is_converted_to_si_with_tension_positive():
    r = parse(_log(), FMT, "a.csv", "a", 0)
    assert r.key == "imported:a" and r.source == "imported" and r.ok
    assert r.channels["x_cmd"][-1] == pytest.approx(0.132)  # 132 mm
    assert r.scalars["peak_detachment"] == pytest.approx(5.0)
    assert r.scalars["peak_pre_pressure"] == pytest.approx(5.0)
    flipped = parse(_log(), config.Logs(tension_positive=False), "a.csv", "a", 0)
    np.testing.assert_allclose(flipped.channels["Fz"], -r.channels["Fz"])


def test_units_in_headers_win_and_fx_is_optional():
    df = _log().drop(columns=["Fx"]).rename(columns={"x": "x [m]", "t": "t [ms]"})
    df["x [m]"] /= 1000
    df["t [ms]"] *= 1000
    r = parse(df, FMT, "b.csv", "b", 0)
    assert r.channels["x_cmd"][-1] == pytest.approx(0.132)
    assert r.channels["t"][-1] == pytest.approx(1.1)
    assert np.isnan(r.channels["Fx"]).all()


@pytest.mark.parametrize(
    ("df", "message"),
    [
        (_log().drop(columns=["Fz"]), "bad.csv: row 1, column 'Fz': missing"),
        (
            _log().rename(columns={"x": "x [inch]"}),
            "bad.csv: row 1, column 'x [inch]': unknown length unit 'inch'",
        ),
        (
            _log(z=[0.0, 1, 2, np.nan, 4, 5, 6, 7, 8, 9, 10, 11]),
            "bad.csv: row 5, column 'z': not a finite number",
        ),
        (
            _log(t=[0.0, 0.1, 0.2, 0.3, 0.25, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1]),
            "bad.csv: row 6, column 't': time does not increase",
        ),
    ],
    ids=["missing-column", "unknown-unit", "nan", "non-monotonic"],
)
def test_a_malformed_log_names_file_row_and_column(df, message):
    with pytest.raises(DataError) as err:
        parse(df, FMT, "bad.csv", "bad", 0)
    assert str(err.value).startswith(message)


def _with_proof(pull: list[float]) -> pd.DataFrame:
    """The step's 12 rows, then a proof pull whose sensor tension runs through ``pull``."""
    step = _log()
    n = len(pull)
    t = step.t.iloc[-1] + 0.05 * np.arange(1, n + 1)
    tail = pd.DataFrame({"t": t, "x": 132.0, "z": 0.0, "Fz": pull, "Fx": 0.0})
    return pd.concat([step.assign(proof=0), tail.assign(proof=1)], ignore_index=True)


def test_a_logged_proof_pull_is_judged_and_the_channels_end_where_it_begins():
    held = parse(_with_proof([2.0, 5.0, 6.5, 6.6, 6.55, 6.6]), FMT, "p.csv", "p", 0, proof_pull=6.6)
    assert held.channels["t"].size == 12 and held.channels["t"][-1] == pytest.approx(1.1)
    assert held.scalars["peak_detachment"] == pytest.approx(5.0)  # the step's, not the pull's
    assert held.scalars["proof_held"] == 1.0 and held.scalars["held_pull"] == 6.6
    assert held.scalars["proof_pull"] == 6.6 and np.isnan(held.scalars["rebond_fraction"])
    on_ramp = parse(_with_proof([2.0, 4.8, 1.0, 0.2]), FMT, "p.csv", "p", 0, proof_pull=6.6)
    assert on_ramp.scalars["proof_held"] == 0.0 and on_ramp.scalars["held_pull"] == 4.8
    in_hold = parse(_with_proof([3.0, 6.6, 6.6, 5.0, 0.1]), FMT, "p.csv", "p", 0, proof_pull=6.6)
    assert in_hold.scalars["proof_held"] == 0.0 and in_hold.scalars["held_pull"] == 6.6


def test_a_log_without_the_phase_carries_no_verdict():
    r = parse(_log(proof=0), FMT, "a.csv", "a", 0, proof_pull=6.6)
    assert r.channels["t"].size == 12 and "proof_held" not in r.scalars


@pytest.mark.parametrize(
    ("df", "force", "message"),
    [
        (
            _with_proof([2.0, 6.6, 6.6]).assign(proof=[0] * 12 + [1, 0, 1]),
            6.6,
            "bad.csv: row 15, column 'proof': the proof pull must run to the log's end",
        ),
        (_log(proof=1), 6.6, "bad.csv: row 2, column 'proof': the log is all proof pull"),
        (
            _with_proof([2.0, 6.6, 6.6]),
            None,
            "bad.csv: column 'proof': the log carries a proof pull, but the robot asks for none",
        ),
    ],
    ids=["gap", "all-pull", "no-proof-robot"],
)
def test_a_malformed_proof_phase_names_file_row_and_column(df, force, message):
    with pytest.raises(DataError) as err:
        parse(df, FMT, "bad.csv", "bad", 0, proof_pull=force)
    assert str(err.value).startswith(message)
