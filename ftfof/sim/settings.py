"""Exudyn's solver settings for a run of the simulator (docs/simulator.md, "Time step")."""

from __future__ import annotations

import math

import exudyn as exu

import ftfof.config as config


def solver_settings(
    solver: config.Solver, end_time: float, step: float, write_rate: float
) -> exu.SimulationSettings:
    """Implicit generalised-alpha to ``end_time`` from steps of ``step`` (the pre-step may change
    it), sparse, no files; sensors stored ``write_rate`` times a second."""
    s = exu.SimulationSettings()
    ti = s.timeIntegration
    ti.endTime = end_time
    ti.numberOfSteps = math.ceil(end_time / step)
    ti.newton.relativeTolerance = solver.tolerance
    ti.newton.absoluteTolerance = solver.tolerance
    ti.generalizedAlpha.spectralRadius = solver.spectral_radius
    ti.adaptiveStep = True
    ti.verboseMode = 0
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    s.solution.file.write = False
    s.solution.sensors.writePeriod = 1.0 / write_rate
    s.show.computationTime = False
    s.show.statistics = False
    return s
