"""Simulate one acquisition: build the platform, run the protocol, return uniform-rate channels.

Protocol (FTFOF §IV.A): settle, press the foot until the sensor reads the pre-pressure a (closed
loop on the sensor, then frozen), run the trajectory, hold the landing with the same commanded
press, stop; what happens between steps is :mod:`ftfof.sim.prestep`. Any Exudyn error, a
non-finite state, or a run stopped before its end (time budget) makes the sample ``failed`` with
the message; partial channels are kept.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import exudyn as exu
import numpy as np
from numpy.typing import NDArray
from scipy import signal

from ftfof.sim import bonds, film
from ftfof.sim.model import Platform, build
from ftfof.sim.prestep import PreStep
from ftfof.sim.records import FailureReason, SampleResult, Status, force_peaks
from ftfof.sim.settings import solver_settings
from ftfof.sim.spec import SampleSpec

Array = NDArray[np.float64]


def _settings(spec: SampleSpec) -> exu.SimulationSettings:
    return solver_settings(
        spec.solver, spec.end_time, spec.solver.free_step, spec.platform.sensor.rate_hz
    )


def simulate(spec: SampleSpec, idle_bonds: bool = True) -> SampleResult:
    """Run one acquisition; never raises for a failing simulation (status = failed).

    A solver failure (with the mixed 500 µs / 2 ms steps, about 1 % of random trajectories,
    after the release, when the free film flew on 2 ms steps) is retried once with a tighter
    tolerance and both steps halved, so a run at one step stays at one step; ``retries``
    records it. Running out of time budget is not retried. A run that fails inside the proof
    pull keeps its step, whole up to the landing hold's end: ok, its pull not measured (NaN).

    ``idle_bonds`` switches off the connectors of broken bonds while their node is clear of the
    plate (:func:`ftfof.sim.bonds.idle_changes`): they pull nothing there, but cost about half
    a run; False keeps them all on (the benchmark's and the test's baseline).
    """
    first = _simulate_once(spec, idle_bonds)
    if first.ok or first.reason is FailureReason.TIME_BUDGET:
        return first
    solver = spec.solver.model_copy(
        update={
            "tolerance": spec.solver.tolerance / 3,
            "step": spec.solver.step / 2,
            "free_step": spec.solver.free_step / 2,
            "phase_steps": {k: h / 2 for k, h in spec.solver.phase_steps.items()},
        }
    )
    second = _simulate_once(replace(spec, solver=solver), idle_bonds)
    second.scalars["retries"] = 1.0
    second.wall_time += first.wall_time
    if not second.ok:
        second.error = f"{second.error} (retried after: {first.error})"
    return second


def _simulate_once(spec: SampleSpec, idle_bonds: bool) -> SampleResult:
    exu.config.printToConsole = False
    started = time.perf_counter()
    law = bonds.BondLaw.from_surface(spec.surface, spec.solver.contact_smoothing)
    platform = build(spec, law)
    solver = exu.MainSolverImplicitSecondOrder()
    run = PreStep(platform, solver, idle_bonds)
    platform.mbs.SetPreStepUserFunction(run)
    if spec.solver.phase_steps:
        platform.mbs.SetPostStepUserFunction(run.after_step)
    reason: FailureReason | None = None
    error = ""
    try:
        solver.SolveSystem(platform.mbs, _settings(spec))
    except exu.ExudynError as err:
        lines = str(err).strip().splitlines()
        reason, error = FailureReason.SOLVER, f"{type(err).__name__}: {lines[-1] if lines else err}"
    end = platform.mbs.systemData.GetTime()
    if reason is None and run.stop_reason is not None:
        reason, error = run.stop_reason, f"stopped early: {run.stop_message}"
    elif reason is None and end < spec.end_time - 1e-9 and not run.proof_let_go:
        reason = FailureReason.STOPPED_EARLY
        error = f"stopped early at t = {end:.4f} s of {spec.end_time:.4f} s"
    if reason is not None and run.proof is not None and run.proof.started:
        # the step's record ended with the landing hold, whole: only the pull is lost (NaN)
        run.proof.lost, reason, error = True, None, ""
    channels = _channels(platform, run)
    if reason is None and not all(np.isfinite(c).all() for c in channels.values()):
        reason, error = FailureReason.NON_FINITE_SENSOR, "non-finite sensor values"
    result = SampleResult(
        spec.key,
        spec.source,
        spec.sample_id,
        Status.OK if reason is None else Status.FAILED,
        error,
        time.perf_counter() - started,
        channels,
        reason=reason,
    )
    result.scalars = summarize(result, run, spec)
    return result


def _channels(p: Platform, run: PreStep) -> dict[str, Array]:
    """Sensor data resampled to the acquisition rate, filtered like the real sensor."""
    spec, mbs = p.spec, p.mbs
    sensor = spec.platform.sensor
    raw = {k: np.asarray(mbs.GetSensorStoredData(v)) for k, v in p.sensors.items()}
    t_end = min(float(raw["Fz"][-1, 0]), spec.landing_end) if len(raw["Fz"]) else 0.0
    t = np.arange(0.0, t_end + 1e-12, 1.0 / sensor.rate_hz)

    def at(name: str, col: int) -> Array:
        data = raw[name]
        if len(data) == 0:
            return np.zeros_like(t)
        return np.interp(t, data[:, 0], data[:, col])

    b, a = signal.butter(2, sensor.cutoff_hz / (sensor.rate_hz / 2))
    rng = np.random.default_rng(spec.seed)

    def measured(name: str) -> Array:
        clean = signal.lfilter(b, a, at(name, 1))
        return clean + rng.normal(0.0, sensor.noise, t.size) if sensor.noise > 0 else clean

    fx, fz = measured("Fx"), measured("Fz")
    # Foot force = force of the pad on the plate = sensor force + plate mass x acceleration
    # (plate EOM), so the plate's own inertia while the linear module moves it is left out.
    mass = sensor.plate_mass
    fx_pad = signal.lfilter(b, a, at("Fx", 1) + mass * at("plate_acc", 1))
    fz_pad = signal.lfilter(b, a, at("Fz", 1) + mass * at("plate_acc", 2))
    tt = t - run.t0
    cmd = spec.trajectory.sample(tt).position[0]
    switch = (
        (t >= run.switched_at) if not math.isnan(run.switched_at) else np.zeros_like(t, dtype=bool)
    )
    log = np.array(run.bond_log)
    event = np.searchsorted(log[:, 0], t, side="right") - 1
    n_bonds = log[event, 1]
    acc = np.hypot(at("body_acc", 1), at("body_acc", 2))
    ankle = spec.mechanics.foot.ankle_height
    return {
        "t": tt,
        "x_cmd": cmd[:, 0],
        "z_cmd": cmd[:, 1],
        "x_foot": at("foot", 1),
        "z_foot": at("foot", 2) - ankle,
        "Fx": fx,
        "Fz": fz,
        "Fx_pad": fx_pad,
        "Fz_pad": fz_pad,
        "Fd": np.maximum(fz_pad, 0.0),
        "Fp": np.maximum(-fz_pad, 0.0),
        "body_acc": acc,
        "bonds": n_bonds.astype(float),
        "switch": switch.astype(float),
        **_film_channels(p, t, tt, np.array(run.bonded_log)[event]),
    }


def _film_channels(p: Platform, t: Array, tt: Array, bonded: Array) -> dict[str, Array]:
    """From the film's node coordinates: the max curvature of its free span
    (:mod:`ftfof.sim.film`; 0 after the pad's first full release) and its clearance, the height
    of its lowest point above the plate (0 while any part of it touches or is bonded)."""
    stored = [np.asarray(p.mbs.GetSensorStoredData(s)) for s in p.film_sensors]
    if len(stored[0]) == 0:
        return {"film_curvature": np.zeros_like(t), "film_clearance": np.zeros_like(t)}
    coords = np.stack([d[:, 1:] for d in stored], axis=1)  # (times, nodes, 4)
    on_grid = _resample(stored[0][:, 0], coords, t)
    kappa = film.free_span_curvature(on_grid, p.x_ref, p.clamp_edge, bonded)
    released = np.cumsum((tt >= 0) & ~bonded.any(axis=1)) > 0
    plate = np.asarray(p.mbs.GetSensorStoredData(p.sensors["plate"]))
    plate_z = np.interp(t, plate[:, 0], plate[:, 2]) if len(plate) else np.zeros_like(t)
    lowest = on_grid[:, :, 1].min(axis=1) - plate_z
    return {
        "film_curvature": np.where(released, 0.0, kappa),
        "film_clearance": np.where(bonded.any(axis=1), 0.0, np.maximum(lowest, 0.0)),
    }


def _resample(times: Array, values: Array, t: Array) -> Array:
    """``values`` (one row per entry of ``times``) linearly interpolated at ``t``, held at the
    ends."""
    if len(times) == 1:
        return np.repeat(values, len(t), axis=0)
    i = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)
    span = times[i + 1] - times[i]
    w = np.clip((t - times[i]) / np.where(span > 0, span, 1.0), 0.0, 1.0)
    w = w.reshape(-1, *([1] * (values.ndim - 1)))
    return values[i] * (1 - w) + values[i + 1] * w


def summarize(result: SampleResult, run: PreStep, spec: SampleSpec) -> dict[str, float]:
    """Per-sample figures: the Table I quantities and diagnostics."""
    c = result.channels
    t = c["t"]
    during = t >= 0
    before = (t > -spec.platform.protocol.press_hold) & (t <= 0)
    bend = float(np.max(c["film_curvature"][during], initial=0.0))
    switched = run.switched_at - run.t0
    holding = during & (c["bonds"] > 0) & ((t <= switched) if not math.isnan(switched) else True)
    return {
        **force_peaks(c["Fx_pad"], c["Fz_pad"], holding),
        "peak_detachment": float(np.max(c["Fd"][during], initial=0.0)),
        "peak_pre_pressure": float(np.max(c["Fp"][during], initial=0.0)),
        "landing_pre_pressure": float(np.max(c["Fp"][c["switch"] > 0], initial=0.0)),
        "initial_pre_pressure": float(np.mean(-c["Fz"][before])) if before.any() else math.nan,
        "peak_body_acc": float(np.max(c["body_acc"][during], initial=0.0)),
        "min_bend_radius": 1.0 / bend if bend > 0 else math.inf,
        "max_clearance": float(np.max(c["film_clearance"][during], initial=0.0)),
        "switch_time": float(run.switched_at - run.t0)
        if not math.isnan(run.switched_at)
        else math.nan,
        "bonds_at_end": float(c["bonds"][-1]) if len(c["bonds"]) else math.nan,
        "steps": float(run.steps),
        "long_steps": float(run.long_steps),
        "retries": 0.0,
        **_proof_figures(run, spec),
    }


def _proof_figures(run: PreStep, spec: SampleSpec) -> dict[str, float]:
    """The landing's re-bond and its proof pull (:mod:`ftfof.sim.proof`): the bonded share of
    the pad's area when the landing hold ended, the pull it held and whether it held F_proof to
    the end (1 or 0; NaN: no proof pull, a run that never reached it or failed in it)."""
    area = run.pad.parts.area
    times = np.array([entry[0] for entry in run.bond_log])
    at_end = run.bonded_log[int(np.searchsorted(times, spec.landing_end, side="right")) - 1]
    out = {
        "rebond_fraction": float(area[at_end].sum() / area.sum()),
        "proof_pull": math.nan if spec.proof_pull is None else spec.proof_pull,
        "held_pull": math.nan,
        "proof_held": math.nan,
    }
    proof = run.proof
    if proof is not None and proof.started and not proof.lost:
        out |= {"held_pull": proof.held_pull, "proof_held": float(proof.held)}
    return out
