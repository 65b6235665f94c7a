"""A finished run in the shapes a notebook uses: Table I, its changes and the surrogates'
fidelity as DataFrames, and the report's own figures (:func:`ftfof.open_run` reads one from a
clone)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from ftfof.evaluate.runs import OPTIMUM
from ftfof.trajectory.bezier import DECISION_NAMES


@dataclass(frozen=True)
class Run:
    """What `evaluate` left in a clone, in the shapes a notebook uses."""

    optimum: dict[str, Any]  # optimum.json: the chosen row, RHS's steps, the simulator's verdicts
    front: pd.DataFrame  # the front, nominees and polished rows, indexed by row
    metrics: dict[str, Any]  # reports/metrics.json
    simulations: pd.DataFrame  # evaluate's successful re-simulations, with their channels

    @property
    def reference(self) -> str:
        return str(self.metrics["reference"])

    @property
    def objectives(self) -> list[str]:
        return list(self.metrics["fidelity"])

    @property
    def table(self) -> pd.DataFrame:
        """Table I as simulated: one row per trajectory, one column per figure (SI units)."""
        rows = self.metrics["table"]
        return pd.DataFrame(
            {n: {k: v for k, v in r.items() if not k.endswith("_change")} for n, r in rows.items()}
        ).T

    @property
    def changes(self) -> pd.DataFrame:
        """Table I in % against :attr:`reference`."""
        rows = self.metrics["table"]
        return pd.DataFrame(
            {
                n: {k.removesuffix("_change"): v for k, v in r.items() if k.endswith("_change")}
                for n, r in rows.items()
            }
        ).T

    @property
    def fidelity(self) -> pd.DataFrame:
        """The surrogates' fidelity on the re-simulated front: objective x statistic."""
        return pd.DataFrame(self.metrics["fidelity"]).T

    def decision(self, row: int | None = None) -> np.ndarray:
        """A front row's control values P3x..P12z (m); the optimum's by default."""
        row = self.optimum["front_row"] if row is None else row
        return self.front.loc[row, list(DECISION_NAMES)].to_numpy(dtype=float)

    def plot_trajectories(self):
        """Foot paths of the optimum and the common trajectories (the report's Fig. 11)."""
        from ftfof.report.evaluation import paths_figure

        return paths_figure(self._channels(), OPTIMUM)

    def plot_forces(self):
        """Detachment force and pre-pressure over the step (the report's Fig. 12)."""
        from ftfof.report.evaluation import forces_figure

        return forces_figure(self._channels(), OPTIMUM)

    def plot_jitter(self):
        """The body's acceleration over the step (the report's Fig. 14)."""
        from ftfof.report.evaluation import jitter_figure

        return jitter_figure(self._channels(), OPTIMUM)

    def plot_front(self):
        """The surrogates' front on every objective, the optimum marked (the report's star)."""
        from ftfof.report.front import star_figure

        names = self.objectives
        members = self.front[names].to_numpy(dtype=float)
        chosen = int(np.flatnonzero(self.front.index == self.optimum["front_row"])[0])
        return star_figure(members, names, chosen, f"front of {len(members)}")

    def _channels(self) -> dict[str, dict[str, np.ndarray]]:
        from ftfof.report.context import plotted_channels

        return plotted_channels(self.simulations, self.reference)
