"""Errors the pipeline reports to users: one line naming what is wrong and where."""

from __future__ import annotations


class FtfofError(Exception):
    """Base of every error a stage turns into a one-line message and a non-zero exit."""

    exit_code = 1

    def __init__(self, where: str, what: str):
        super().__init__(f"{where}: {what}" if where else what)
        self.where = where
        self.what = what


class ParamsError(FtfofError):
    """A params.yaml key with a wrong name, type or value."""

    exit_code = 2


class InfeasibleRobotError(FtfofError):
    """A robot description whose constraints cannot all hold (e.g. a lower bound above an upper)."""

    exit_code = 2


class SamplingError(FtfofError):
    """Not enough feasible trajectories within the draw budget."""


class DataError(FtfofError):
    """A corrupt, truncated or schema-mismatched input file."""


class SimulationError(FtfofError):
    """A simulation that raised, diverged or stopped early."""


class OptimizationError(FtfofError):
    """A search that found no feasible trajectory, or none that survives the independent recheck."""
