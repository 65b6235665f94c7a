"""Fit a surface to FTFOF Table I with the polynomial and cycloidal baselines (docs/simulator.md).

Fits the adhesive strength and fracture energy (either may be held fixed instead), plus at most
two more parameters (one of the surface's, and the plate foot's backing modulus), so the
simulated max detachment force and max pre-pressure of the two baselines land on the published
values: four targets, at most four values. Only baselines enter the fit; the optimum's improvement
stays a prediction. The fit says which of its values sit on a bound or on the fracture-energy cap:
there Table I does not decide the value, the bound does. :func:`surface_fit` fits under the
robot's film cap and reports it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import minimize

import ftfof.config as config
from ftfof.errors import ParamsError
from ftfof.identify.calibration import fit_bounds
from ftfof.sim import film
from ftfof.sim.pool import run_all
from ftfof.sim.records import SampleResult
from ftfof.sim.spec import SampleSpec

# FTFOF Table I (N): the two common trajectories the fit may use.
TABLE_I: dict[str, dict[str, float]] = {
    "polynomial": {"peak_detachment": 7.49, "peak_pre_pressure": 5.41},
    "cycloidal": {"peak_detachment": 7.24, "peak_pre_pressure": 5.21},
}
ADHESION = ("strength", "fracture_energy")
MEASURED = ("min_bend_radius", "peak_pull")  # reported beside Table I's, never fitted
AT_BOUND = 5e-3  # a value this close (relative) to a bound or the cap sits on it
LOG_SCALED = {
    "strength",
    "fracture_energy",
    "rate_speed",
    "preload_pressure",
    "contact_stiffness",
    "backing_modulus",
}
FOOT = {"backing_modulus": "modulus"}  # fitted values of the foot's backing, not the surface
SpecsFor = Callable[[config.Surface, config.FootMechanics], list[SampleSpec]]


@dataclass
class Calibration:
    values: dict[str, float]
    residuals: dict[str, float]  # relative error per baseline and quantity
    measured: dict[str, dict[str, float]]
    evaluations: int
    history: list[dict[str, float]] = field(default_factory=list)
    active: dict[str, str] = field(default_factory=dict)  # name -> the bound or cap it sits on

    @property
    def worst(self) -> float:
        return max(abs(v) for v in self.residuals.values())


def _measure(results: Sequence[SampleResult]) -> dict[str, dict[str, float]]:
    out = {}
    for r in results:
        name = r.source.removeprefix("baseline:")
        if name not in TABLE_I:  # e.g. the random Bezier or the paper's optimum: held out
            raise ValueError(f"only {', '.join(TABLE_I)} may enter the fit (got {r.source})")
        # a failed run measures no force (Table I's error is then -100 %) and no film at all
        out[name] = {
            **{q: (r.scalars.get(q, 0.0) if r.ok else 0.0) for q in TABLE_I[name]},
            **{q: (r.scalars.get(q) if r.ok else None) for q in MEASURED},
        }
    return out


def _residuals(measured: dict[str, dict[str, float]]) -> dict[str, float]:
    return {
        f"{name}.{q}": measured[name][q] / target - 1.0
        for name, targets in TABLE_I.items()
        for q, target in targets.items()
    }


def trial_of(
    surface: config.Surface, foot: config.FootMechanics, values: dict[str, float]
) -> tuple[config.Surface, config.FootMechanics]:
    """The surface and the foot with ``values`` set: the backing's keys on the foot's backing,
    the rest on the surface."""
    backing = {FOOT[k]: v for k, v in values.items() if k in FOOT}
    if backing:
        assert foot.backing is not None, "only a plate foot's backing can be fitted"
        foot = foot.model_copy(update={"backing": foot.backing.model_copy(update=backing)})
    on_surface = {k: v for k, v in values.items() if k not in FOOT}
    return surface.model_copy(update=on_surface), foot


def fit_start(
    name: str,
    robot: config.Robot,
    surface: config.Surface,
    third: str | None,
    fixed: dict[str, float],
    bounds: dict[str, tuple[float, float]],
) -> tuple[dict[str, tuple[float, float]], config.Surface, config.Robot]:
    """A fit's ranges (:func:`ftfof.identify.calibration.fit_bounds`, ``bounds`` overriding),
    its start (``fixed`` set on ``surface``) and robot ``name`` on the start's foot; a backing
    modulus held or bounded is refused where the foot has no backing."""
    foot = robot.platform.foot
    if "backing_modulus" in {*fixed, *bounds} and foot.model != "plate":
        raise ParamsError("--fix/--bound backing_modulus", f"{name}'s foot has no backing")
    fitted = fit_bounds(third, fixed, bounds, backing=foot.model == "plate")
    start, foot = trial_of(surface, foot, fixed)
    return fitted, start, with_foot(robot, foot)


def with_foot(robot: config.Robot, foot: config.FootMechanics) -> config.Robot:
    """``robot`` on ``foot`` (a trial's backing)."""
    return robot.model_copy(update={"platform": robot.platform.model_copy(update={"foot": foot})})


def start_value(surface: config.Surface, foot: config.FootMechanics, name: str) -> float:
    """A fitted parameter's value in ``surface`` or ``foot`` (the fit's start)."""
    if name in FOOT:
        assert foot.backing is not None, "only a plate foot's backing can be fitted"
        return float(getattr(foot.backing, FOOT[name]))
    return float(getattr(surface, name))


class _Scale:
    """The fit's coordinates: the log of the positive scales, mapped back within the bounds and
    under the fracture-energy cap."""

    def __init__(self, names: list[str], bounds: dict[str, tuple[float, float]], cap: float | None):
        self.logs = np.array([n in LOG_SCALED for n in names])
        self.lo = np.array([bounds[n][0] for n in names], dtype=float)
        self.hi = np.array([bounds[n][1] for n in names], dtype=float)
        self.cap = cap
        self.i_energy = names.index("fracture_energy") if "fracture_energy" in names else None

    def to_x(self, values: np.ndarray) -> np.ndarray:
        return np.where(self.logs, np.log(values), values)

    def from_x(self, x: np.ndarray) -> np.ndarray:
        v = np.clip(np.where(self.logs, np.exp(x), x), self.lo, self.hi)
        if self.i_energy is not None and self.cap is not None:
            v[self.i_energy] = min(v[self.i_energy], self.cap)
        return v

    def simplex(self, start: np.ndarray) -> np.ndarray:
        """Nelder-Mead's first simplex: ``start`` and a step from it along each parameter."""
        x0 = self.to_x(start)
        steps = np.where(self.logs, 0.3, 0.15)
        i = self.i_energy
        if self.cap is not None and i is not None and start[i] >= self.cap * (1 - AT_BOUND):
            steps[i] *= -1  # a start on the cap: step below it, or the vertex is the start
        n = len(steps)
        return np.vstack([x0] + [x0 + np.eye(n)[k] * steps[k] for k in range(n)])


class _Trials:
    """The fit's cost of a point, each distinct trial simulated once, and the trials' history."""

    def __init__(
        self,
        surface: config.Surface,
        foot: config.FootMechanics,
        specs_for: SpecsFor,
        names: list[str],
        scale: _Scale,
        workers: int,
    ):
        self.surface, self.foot, self.specs_for = surface, foot, specs_for
        self.names, self.scale, self.workers = names, scale, workers
        self.history: list[dict[str, float]] = []
        self.cache: dict[tuple[float, ...], tuple[float, dict]] = {}

    def cost(self, x: np.ndarray) -> float:
        values = self.scale.from_x(x)
        key = tuple(np.round(values, 12))
        if key not in self.cache:
            named = dict(zip(self.names, map(float, values), strict=True))
            trial = trial_of(self.surface, self.foot, named)
            measured = _measure(run_all(self.specs_for(*trial), self.workers))
            res = np.array(list(_residuals(measured).values()))
            # Table I is met quantity by quantity: minimise the worst relative error first.
            cost = float(np.max(np.abs(res)) + 0.1 * np.mean(res**2))
            self.cache[key] = (cost, measured)
            self.history.append({**named, "cost": cost})
        return self.cache[key][0]

    def measured(self, x: np.ndarray) -> dict[str, dict[str, float]]:
        """What the trial at ``x`` measured (simulated now if it was not yet)."""
        self.cost(x)
        return self.cache[tuple(np.round(self.scale.from_x(x), 12))][1]


def calibrate(
    surface: config.Surface,
    foot: config.FootMechanics,
    specs_for: SpecsFor,
    bounds: dict[str, tuple[float, float]],
    workers: int = 0,
    max_evaluations: int = 80,
    max_fracture_energy: float | None = None,
) -> Calibration:
    """Nelder-Mead on the named parameters (log scale where positive scales) within ``bounds``,
    minimising the worst relative error against Table I; the surface's other values stay.

    ``max_fracture_energy`` caps G (ftfof.sim.film.survival_energy: the film survives its
    adhesive's steady peels at fc). Table I's two peaks move with sigma and G together, so
    along that ridge G is set by the cap or a bound, which ``Calibration.active`` names.
    """
    names = list(bounds)
    on_surface = [n for n in names if n not in ADHESION and n not in FOOT]
    if not names or len(on_surface) > 1 or (set(names) & set(FOOT) and foot.backing is None):
        raise ValueError(
            "fit strength and/or fracture energy, at most one more surface value and a plate"
            f" foot's backing (got {names or 'none'})"
        )
    scale = _Scale(names, bounds, max_fracture_energy)
    trials = _Trials(surface, foot, specs_for, names, scale, workers)
    # the surface's values within the bounds and the cap
    start = scale.from_x(scale.to_x(np.array([start_value(surface, foot, n) for n in names])))
    result = minimize(
        trials.cost,
        scale.to_x(start),
        method="Nelder-Mead",
        options={
            "initial_simplex": scale.simplex(start),
            "maxfev": max_evaluations,
            "xatol": 1e-3,
            "fatol": 1e-6,
        },
    )
    values = dict(zip(names, map(float, scale.from_x(result.x)), strict=True))
    measured = trials.measured(result.x)
    return Calibration(
        values=values,
        residuals=_residuals(measured),
        measured=measured,
        evaluations=len(trials.history),
        history=trials.history,
        active=_active(values, bounds, max_fracture_energy),
    )


def fracture_energy_cap(robot: config.Robot) -> float | None:
    """The grip foot's cap on G: its free film survives a steady peel at fc
    (docs/decisions/0013). The plate backs the whole film, so no steady peel bends it: none."""
    if robot.platform.foot.model == "plate":
        return None
    f = robot.platform.film
    return film.survival_energy(f.bending_stiffness, f.width, robot.foot.film_min_bend_radius)


def surface_fit(
    robot: config.Robot,
    start: config.Surface,
    specs_for: SpecsFor,
    bounds: dict[str, tuple[float, float]],
    fixed: dict[str, float],
    workers: int,
    evaluations: int,
) -> dict[str, Any]:
    """:func:`calibrate` of ``bounds``'s parameters from ``start`` and the robot's foot (``fixed``
    held there), the fracture energy capped where the film needs it (:func:`fracture_energy_cap`),
    and the report of the fit: where it sits on a bound or the cap, and what it does to the film
    (:func:`film_report`)."""
    cap = fracture_energy_cap(robot)
    foot = robot.platform.foot
    fit = calibrate(start, foot, specs_for, bounds, workers, evaluations, cap)
    surface, _ = trial_of(start, foot, fit.values)
    active = dict(fit.active)
    if cap is not None and fixed.get("fracture_energy", 0.0) > cap:  # held there by hand
        active["fracture_energy"] = "fixed above the fracture-energy cap"
    return {
        "targets": TABLE_I,
        "values": fit.values,
        "fixed": fixed,
        "bounds": {k: list(v) for k, v in bounds.items()},
        "fracture_energy_cap": cap,
        "active": active,
        "residuals": fit.residuals,
        "measured": fit.measured,
        "worst_relative_error": fit.worst,
        "film": film_report(robot, surface, fit.measured),
        "evaluations": fit.evaluations,
        "history": fit.history,
    }


def _active(
    values: dict[str, float], bounds: dict[str, tuple[float, float]], cap: float | None
) -> dict[str, str]:
    """Which fitted values sit on what: 'lower bound', 'upper bound' or 'fracture-energy cap'."""
    out = {}
    for name, value in values.items():
        lo, hi = bounds[name]
        if name == "fracture_energy" and cap is not None and value >= cap * (1 - AT_BOUND):
            out[name] = "fracture-energy cap"
        elif value <= lo * (1 + AT_BOUND):
            out[name] = "lower bound"
        elif value >= hi * (1 - AT_BOUND):
            out[name] = "upper bound"
    return out


def film_report(
    robot: config.Robot, surface: config.Surface, measured: dict[str, dict[str, float]]
) -> dict:
    """What the fitted surface does to the robot's film: the bond's critical opening, the steady
    peel's root radius against fc, and each baseline's clamp edge under its peak pull."""
    f, fc = robot.platform.film, robot.foot.film_min_bend_radius
    ei, g = f.bending_stiffness, surface.fracture_energy
    baselines = {}
    for name, m in measured.items():
        pull = m["peak_pull"]  # the resultant: the film's tension at the clamp
        ran = pull is not None and pull > 0
        baselines[name] = {
            "min_bend_radius": m["min_bend_radius"],  # measured on the free span; None: failed
            "peak_pull": pull,
            # elastica at the clamp edge, were the peak pull at 90 deg to the film in the clamp
            # (a hypothetical case: the bound's size), and the largest such angle keeping fc
            "clamp_edge_radius_if_pulled_at_90deg": film.clamp_edge_radius(ei, pull, math.pi / 2)
            if ran
            else None,
            "max_angle_keeping_fc_deg": math.degrees(film.max_pull_angle(ei, pull, fc))
            if ran
            else None,
        }
    return {
        "fc": fc,
        "bending_stiffness": ei,
        "axial_stiffness": f.axial_stiffness,
        "critical_opening": 2.0 * g / surface.strength,
        "peel_root_radius": film.peel_root_radius(ei, f.width, g),
        "survival_energy": film.survival_energy(ei, f.width, fc),
        "baselines": baselines,
    }
