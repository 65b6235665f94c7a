"""The proof pull: after the landing hold, does the landed pad hold the robot's stance demand?

On the climbing robot a fore foot that has just landed is pulled at its ankle by the next fore
landing's press and the trunk's tip, a + m g h / L (:func:`ftfof.demand.fore_foot_demand`). A real
platform can test that with what it has: the press loop on its force sensor moves the load from
the held landing press to a pull of F_proof over ``proof_ramp`` and keeps it ``proof_hold``, and
the test ends as soon as a further tenth of the pad's area has let go (of the share the landing
bonded: a landing that re-bonded little is tested on what it bonded), before the pull can tear
the rest (the pad survives the test). It reports whether the pad held, and ``held_pull``: the
largest pull it bore before that tenth let go, at most F_proof (a pad that lets go in the hold
bore F_proof, then failed as its bonds' rate strength faded: it did not hold).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ftfof.demand import LET_GO, REACHED
from ftfof.sim.model import Platform
from ftfof.sim.press import press_control, press_to_pull, sensor_tension

Array = NDArray[np.float64]


class ProofPull:
    """The proof pull's press loop, run by the pre-step from the landing hold's end."""

    def __init__(self, p: Platform, plate_index: int):
        spec = p.spec
        assert spec.proof_pull is not None
        proto = spec.platform.protocol
        self.p, self.plate_index = p, plate_index
        self.force, self.start, self.ramp = spec.proof_pull, spec.landing_end, proto.proof_ramp
        self.sensor = spec.platform.sensor
        self.from_press = math.nan  # N: the compression the sensor read when the pull began
        self.from_share = math.nan  # the pad's bonded share when the pull began
        self.integral = 0.0
        self.peak = 0.0  # N: the largest tension the sensor has read in the pull
        self.let_go = False
        self.lost = False  # the run failed inside the pull before it was judged

    @property
    def started(self) -> bool:
        """The pull has begun: the landing hold's record is whole."""
        return not math.isnan(self.from_press)

    @property
    def held(self) -> bool:
        """The pad bore F_proof to the end without letting a further tenth go (call it once the
        run has reached its end)."""
        return not self.let_go and self.peak >= REACHED * self.force

    @property
    def held_pull(self) -> float:
        """The largest pull the pad bore before a tenth of it let go, at most F_proof (N)."""
        return self.force if self.held else min(self.peak, self.force)

    def __call__(self, t: float, q: Array, qd: Array, h: float, bonded_share: float) -> bool:
        """One step of the pull from ``t``; False once a further tenth of the pad has let go."""
        tension = sensor_tension(self.sensor, self.plate_index, q, qd)
        self.peak = max(self.peak, tension)
        if not self.started:
            # the loop takes over from the landing's press depth where it stands, without a jump
            self.from_press, self.from_share = -tension, bonded_share
            depth = float(self.p.press_depth.Evaluate())
            self.integral = depth - self.from_press / self.p.series_stiffness
        if bonded_share < (1.0 - LET_GO) * self.from_share or self.from_share <= LET_GO:
            # (a landing that bonded no more than a tenth has nothing to hold with)
            self.let_go = True
            return False
        u = min((t - self.start) / self.ramp, 1.0)
        target = press_to_pull(self.from_press, self.force, u)
        self.integral = press_control(self.p, self.plate_index, q, qd, h, target, self.integral)
        return True
