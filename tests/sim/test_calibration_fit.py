"""The calibration fit on a synthetic surface model: no simulator, the parameter update alone."""

from types import SimpleNamespace

import numpy as np
import pytest

from ftfof.sim import calibrate as cal

TRUE = {"strength": 20000.0, "fracture_energy": 40.0}
START = {"strength": 24000.0, "fracture_energy": 54.0}


def _model(strength: float, energy: float, failing=()):
    """A stand-in for `run_all`: Table I exactly at ``true``, Kendall-like scaling around it."""

    def run_all(specs, workers):
        s, g = specs[0][1].strength / strength, specs[0][1].fracture_energy / energy
        out = []
        for name, _ in specs:
            t = cal.TABLE_I[name]
            scalars = {
                "peak_detachment": t["peak_detachment"] * np.sqrt(s * g),
                "peak_pre_pressure": t["peak_pre_pressure"] * np.sqrt(s) * g**-0.25,
            }
            ok = name not in failing
            out.append(SimpleNamespace(source=f"baseline:{name}", ok=ok, scalars=scalars))
        return out

    return run_all


BOUNDS = {"strength": (5e3, 1e5), "fracture_energy": (5.0, 500.0)}


def _fit(monkeypatch, params, true=TRUE, failing=(), cap=None, bounds=BOUNDS, start=START):
    run_all = _model(true["strength"], true["fracture_energy"], failing)
    monkeypatch.setattr(cal, "run_all", run_all)
    # a fixed start, so the test does not follow the repository's calibrated values
    surface = params.surfaces["acrylic"].model_copy(update=start)
    return cal.calibrate(
        surface,
        params.selected_robot.platform.foot,
        lambda trial, foot: [(name, trial) for name in cal.TABLE_I],
        bounds,
        max_evaluations=200,
        max_fracture_energy=cap,
    )


def test_the_fit_recovers_the_surface_that_reproduces_table_i(monkeypatch, params):
    assert abs(START["strength"] / TRUE["strength"] - 1) > 0.1  # the fit has somewhere to go
    fit = _fit(monkeypatch, params)
    assert fit.values == pytest.approx(TRUE, rel=0.02)
    assert fit.worst < 0.01
    assert set(fit.residuals) == {f"{n}.{q}" for n, t in cal.TABLE_I.items() for q in t}
    assert fit.evaluations == len(fit.history) > 3
    assert fit.measured["polynomial"]["peak_detachment"] == pytest.approx(7.49, rel=0.01)
    assert fit.active == {}  # inside every bound: Table I decided each value


def test_the_fracture_energy_cap_holds_and_the_fit_says_it_sits_on_it(monkeypatch, params):
    """Table I wants G = 80 J/m^2 here, but the film's survival caps it at 50."""
    fit = _fit(monkeypatch, params, {"strength": 20000.0, "fracture_energy": 80.0}, (), 50.0)
    assert all(trial["fracture_energy"] <= 50.0 for trial in fit.history)
    assert fit.values["fracture_energy"] == pytest.approx(50.0)
    assert fit.active == {"fracture_energy": "fracture-energy cap"}
    # the start (54) sits past the cap: the first simplex steps below it, not back onto it
    assert min(trial["fracture_energy"] for trial in fit.history[:3]) < 0.8 * 50.0
    assert fit.worst > 0.05  # the capped surface cannot meet Table I


def test_a_held_value_stays_and_a_bound_that_stops_the_fit_is_named(monkeypatch, params):
    """Strength alone, bounded below the 20 kPa Table I wants, with G held at its true 40."""
    bounds = {"strength": (5e3, 1.5e4)}
    start = {"strength": 1.2e4, "fracture_energy": 40.0}
    fit = _fit(monkeypatch, params, TRUE, (), None, bounds, start)
    assert set(fit.values) == {"strength"} and fit.values["strength"] == pytest.approx(1.5e4)
    assert all(set(trial) == {"strength", "cost"} for trial in fit.history)
    assert fit.active == {"strength": "upper bound"}


def test_a_failed_baseline_measures_zero_force(monkeypatch, params):
    fit = _fit(monkeypatch, params, TRUE, ("cycloidal",))
    assert fit.measured["cycloidal"] == {
        "peak_detachment": 0.0,
        "peak_pre_pressure": 0.0,
        "min_bend_radius": None,  # a failed run bent no film: not a crushed one
        "peak_pull": None,
    }
    assert fit.residuals["cycloidal.peak_detachment"] == -1.0 and fit.worst == 1.0


@pytest.mark.parametrize("held_out", ["random_bezier", "paper_optimum"])
def test_a_held_out_trajectory_cannot_enter_the_fit(monkeypatch, params, held_out):
    def run_all(specs, workers):
        return [SimpleNamespace(source=f"baseline:{held_out}", ok=True, scalars={})]

    monkeypatch.setattr(cal, "run_all", run_all)
    bounds = {"strength": (5e3, 1e5), "fracture_energy": (5.0, 500.0)}
    with pytest.raises(ValueError, match=f"only polynomial, cycloidal .*{held_out}"):
        cal.calibrate(
            params.surfaces["acrylic"],
            params.selected_robot.platform.foot,
            lambda trial, foot: [],
            bounds,
            max_evaluations=4,
        )


def test_ftfof_calibrate_simulates_the_polynomial_and_the_cycloid_only(monkeypatch, params):
    from ftfof.pipeline import calibration

    seen = []

    def fake_calibrate(surface, foot, specs_for, bounds, workers, evaluations, cap):
        seen.extend(spec.source for spec in specs_for(surface, foot))
        return SimpleNamespace(
            values={}, residuals={}, measured={}, worst=0.0, evaluations=0, history=[], active={}
        )

    monkeypatch.setattr(cal, "calibrate", fake_calibrate)
    calibration.fit_surface(params, "none", 4)
    assert seen == ["baseline:polynomial", "baseline:cycloidal"]
    # the grip foot's G held above its film's cap by hand: the report says so beside the value
    report = calibration.fit_surface(_grip(params), "none", 4, {"fracture_energy": 200.0})
    assert report["active"] == {"fracture_energy": "fixed above the fracture-energy cap"}
    assert report["foot"] == "grip"
    # the plate backs its film: no cap
    assert calibration.fit_surface(params, "none", 4, {"fracture_energy": 200.0})["active"] == {}


def _grip(params):
    """``params`` with the selected robot on the grip foot (its film clamped at the heel)."""
    data = params.model_dump()
    foot = data["robots"][data["robot"]]["platform"]["foot"]
    foot.update(model="grip", backing=None, ankle_range=None)
    return type(params).model_validate(data)


def test_the_fit_report_names_the_films_cap_and_a_value_held_above_it(monkeypatch, params):
    from ftfof.sim import film

    monkeypatch.setattr(cal, "run_all", _model(TRUE["strength"], TRUE["fracture_energy"]))
    robot = _grip(params).selected_robot
    start = params.surfaces["acrylic"].model_copy(update={**START, "fracture_energy": 1e4})
    report = cal.surface_fit(
        robot,
        start,
        lambda trial, foot: [(name, trial) for name in cal.TABLE_I],
        {"strength": (5e3, 1e5)},
        {"fracture_energy": 1e4},
        0,
        40,
    )
    assert list(report) == [
        "targets", "values", "fixed", "bounds", "fracture_energy_cap", "active", "residuals",
        "measured", "worst_relative_error", "film", "evaluations", "history",
    ]  # fmt: skip
    f = robot.platform.film
    cap = film.survival_energy(f.bending_stiffness, f.width, robot.foot.film_min_bend_radius)
    assert report["fracture_energy_cap"] == cap < 1e4
    assert report["active"]["fracture_energy"] == "fixed above the fracture-energy cap"
    assert report["bounds"] == {"strength": [5e3, 1e5]} and report["fixed"] == {
        "fracture_energy": 1e4
    }
    assert report["film"]["fc"] == robot.foot.film_min_bend_radius
    assert report["evaluations"] == len(report["history"]) <= 40


def test_a_plate_foots_backing_is_fitted_beside_the_surface(monkeypatch, params):
    """Table I's pre-pressure rises with the backing's modulus, the pull with the strength."""
    from ftfof.config import FootMechanics
    from tests.sim.test_foot import PLATE

    true_strength, true_modulus = 20000.0, 2.0e6

    def run_all(specs, workers):
        out = []
        for name, surface, foot in specs:
            s = surface.strength / true_strength
            e = foot.backing.modulus / true_modulus
            t = cal.TABLE_I[name]
            scalars = {
                "peak_detachment": t["peak_detachment"] * s**0.5 * e**0.1,
                "peak_pre_pressure": t["peak_pre_pressure"] * s**0.05 * e**0.3,
            }
            out.append(SimpleNamespace(source=f"baseline:{name}", ok=True, scalars=scalars))
        return out

    monkeypatch.setattr(cal, "run_all", run_all)
    plate = FootMechanics.model_validate(PLATE)  # starts at 1 MPa
    surface = params.surfaces["acrylic"].model_copy(update=START)
    bounds = {"strength": (5e3, 1e5), "backing_modulus": (1e5, 1e7)}

    def specs_for(trial, foot):
        return [(name, trial, foot) for name in cal.TABLE_I]

    fit = cal.calibrate(surface, plate, specs_for, bounds, max_evaluations=200)
    assert fit.values["strength"] == pytest.approx(true_strength, rel=0.02)
    assert fit.values["backing_modulus"] == pytest.approx(true_modulus, rel=0.02)
    assert fit.worst < 0.01 and fit.active == {}
    fitted_surface, fitted_foot = cal.trial_of(surface, plate, fit.values)
    assert fitted_foot.backing.modulus == fit.values["backing_modulus"]
    assert fitted_surface.strength == fit.values["strength"]
    grip = plate.model_copy(update={"model": "grip", "backing": None})
    with pytest.raises(ValueError, match="a plate foot's backing"):
        cal.calibrate(surface, grip, specs_for, bounds, max_evaluations=4)
