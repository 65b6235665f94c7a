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
