"""Is the film's bend converged where fc is judged? The optimum, the front members and Table I's
trajectories simulated again on ``evaluate.check_nodes`` film elements, beside the acquisition's.

fc is a rule on the free span's tightest bend (ftfof/sim/film.py), which the optimiser saw at the
acquisition's node count only. A bend at the clamp edge is a boundary layer about sqrt(EI / F)
long, so a coarse film can round it off; this check puts each run's min bend radius at both
counts side by side and names the runs that keep fc on one film and not on the other.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

FILM = "film:"  # source prefix of the runs on the check film


@dataclass(frozen=True)
class FilmCheck:
    """Min bend radius (m) by run name at the acquisition's ``nodes`` and at ``check_nodes``."""

    nodes: int
    check_nodes: int
    fc: float
    at_nodes: Mapping[str, float]
    at_check: Mapping[str, float]

    def pair(self, name: str) -> tuple[float, float] | None:
        """The run's radius on both films; None where either run is missing."""
        if name not in self.at_nodes or name not in self.at_check:
            return None
        return self.at_nodes[name], self.at_check[name]

    def as_dict(self) -> dict:
        """For metrics.json: every run's radius on both films, its change, and which keep fc on
        the acquisition's film but not on the check film (or the other way round)."""
        both = [n for n in self.at_nodes if n in self.at_check]
        radius = {n: [round(self.at_nodes[n], 6), round(self.at_check[n], 6)] for n in both}
        return {
            "nodes": self.nodes,
            "check_nodes": self.check_nodes,
            "fc": self.fc,
            "radius": radius,
            "change": {n: round(self.at_check[n] / self.at_nodes[n] - 1, 4) for n in both},
            "max_abs_change": round(
                max((abs(self.at_check[n] / self.at_nodes[n] - 1) for n in both), default=0.0), 4
            ),
            "keeps_fc_only_at_nodes": [
                n for n in both if self.at_nodes[n] >= self.fc > self.at_check[n]
            ],
            "keeps_fc_only_at_check": [
                n for n in both if self.at_check[n] >= self.fc > self.at_nodes[n]
            ],
            "missing": sorted(set(self.at_nodes) ^ set(self.at_check)),
        }
