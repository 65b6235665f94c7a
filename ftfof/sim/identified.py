"""The slip test `ftfof identify` runs and what the bond law says of its estimate: the friction
and adhesion a preset implies (:func:`truth`), and the preset an estimate gives
(:func:`identified_preset`)."""

from __future__ import annotations

from typing import Any

import ftfof.config as config
from ftfof.identify.estimate import Estimate
from ftfof.identify.fit import preset_block
from ftfof.identify.log import SlipLog
from ftfof.sim.bonds import BondLaw
from ftfof.sim.slip import SlipProtocol, adhesion_truth, drag, slip_test, strength_for
from ftfof.sim.spec import Bench

# the slip test of `ftfof slip-test` and `ftfof identify --simulate`
PROTOCOL = SlipProtocol(
    loads=(-1.0, 0.0, 1.0, 2.0, 3.0, 4.0), speed=0.01, drag=0.008, ankle_stiffness=50.0
)


def simulated_log(on: Bench, protocol: SlipProtocol = PROTOCOL) -> SlipLog:
    """The slip test of ``on``'s robot's pad on its surface."""
    return slip_test(on.spec("slip", 0, drag(protocol.speed, protocol.drag)), protocol)


def truth(law: BondLaw, robot: config.Robot) -> Estimate:
    """mu and F_adh per pad the preset's bond ``law`` implies (:func:`adhesion_truth`)."""
    return Estimate(law.friction, adhesion_truth(law, robot.pre_pressure, robot.pad_area))


def identified_preset(
    law: BondLaw,
    robot: config.Robot,
    surface: config.Surface,
    source: str,
    est: Estimate,
    pull_off: float | None = None,
) -> dict[str, Any]:
    """``surface``'s preset with the identified friction and the shear strength tau_max that
    gives the identified adhesion at the robot's preload (:func:`strength_for`,
    :func:`ftfof.identify.fit.preset_block`)."""
    tau = strength_for(law, robot.pre_pressure, robot.pad_area, est.mu, est.adhesion)
    return preset_block(surface, source, est.mu, tau, pull_off)
