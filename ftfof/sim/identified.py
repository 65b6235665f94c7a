"""The slip test `ftfof identify` runs and what the bond law says of its estimate: the friction
and adhesion a preset implies (:func:`truth`), the rate law two drag speeds give
(:func:`rate_law`), and the preset an estimate gives (:func:`identified_preset`); and the same
for the slip bench of a surface preset (:func:`law_of`), as the report writes them."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import ftfof.config as config
from ftfof.identify.estimate import Estimate
from ftfof.identify.fit import identify, preset_block
from ftfof.identify.log import SlipLog
from ftfof.sim.bonds import BondLaw
from ftfof.sim.slip import SlipProtocol, adhesion_truth, drag, slip_test, strength_for
from ftfof.sim.spec import Bench

# the slip test of `ftfof slip-test` and `ftfof identify --simulate`: a drag stage's stiff drive
# in the pad's plane, slow enough that the bonds shear at the drag speed from its ramp on; the
# loads press (0 up to the preload): a pulled pad presses no node, so its friction is nil, not
# mu F_n < 0 (docs/decisions/0027)
PROTOCOL = SlipProtocol(
    loads=(0.0, 1.0, 2.0, 3.0, 4.0, 5.0),
    speed=0.001,
    drag=0.0005,
    ankle_stiffness=50.0,
    drive_stiffness=2.0e7,
    drive_height=1.0e-3,
    coupon_modulus=1.0e8,  # a hard plastic plate: 100 MPa over the backing's 3 mm
)


def simulated_log(on: Bench, protocol: SlipProtocol = PROTOCOL) -> SlipLog:
    """The slip test of ``on``'s robot's pad on its surface."""
    return slip_test(on.spec("slip", 0, drag(protocol.speed, protocol.drag)), protocol)


def truth(law: BondLaw, robot: config.Robot, speed: float = PROTOCOL.speed) -> Estimate:
    """mu and F_adh(v) per pad the preset's bond ``law`` implies at drag ``speed``
    (:func:`adhesion_truth`)."""
    return Estimate(law.friction, adhesion_truth(law, robot.pre_pressure, robot.pad_area, speed))


def quasi_static(law: BondLaw, adhesion: float, speed: float) -> float:
    """F_adh,0 of a pad that held ``adhesion`` dragged at ``speed``: F_adh(v) / R(v), R from the
    law's rate exponent and speed (the preset's, or :func:`rate_law`'s)."""
    return adhesion / law.drag_rate_factor(speed)


@dataclass(frozen=True)
class RateLaw:
    exponent: float  # n
    speed: float  # v*, m/s of normal opening


def rate_law(law: BondLaw, adhesion_0: float, drags: dict[float, float]) -> RateLaw:
    """n and v* of R = 1 + (v / v*)^n from F_adh at two drag speeds, F_adh,0 known.

    Each speed gives R_i - 1 = F_adh(v_i) / F_adh,0 - 1 = (c v_i / v*)^n, with c = d_n / d_t
    the law's ratio of normal to shear opening (a drag at v opens the bonds at c v in the units
    of v*, :meth:`BondLaw.drag_rate_factor`). Two of them: n = ln((R_1 - 1) / (R_2 - 1)) /
    ln(v_1 / v_2), then v* = c v_1 / (R_1 - 1)^(1/n). Assumed known: F_adh,0 (the preset's tau,
    from the pull-off calibration and k, or a quasi-static test) and c (the preset's k and
    G_II / G); a third speed would free F_adh,0 too."""
    if len(drags) != 2:
        raise ValueError(f"the rate law needs two drag speeds, got {sorted(drags)}")
    (v1, f1), (v2, f2) = sorted(drags.items())
    g1, g2 = f1 / adhesion_0 - 1.0, f2 / adhesion_0 - 1.0
    if not 0.0 < g1 < g2:
        raise ValueError(f"F_adh must rise with the speed above F_adh,0 = {adhesion_0:.3f} N")
    n = math.log(g2 / g1) / math.log(v2 / v1)
    c = law.critical_opening / law.shear_opening
    return RateLaw(n, c * v1 / g1 ** (1.0 / n))


def identified_preset(
    law: BondLaw,
    robot: config.Robot,
    surface: config.Surface,
    source: str,
    est: Estimate,
    pull_off: float | None = None,
) -> dict[str, Any]:
    """``surface``'s preset with the identified friction and the shear strength tau_max that
    gives the identified quasi-static adhesion ``est.adhesion`` (F_adh,0) at the robot's preload
    (:func:`strength_for`, :func:`ftfof.identify.fit.preset_block`)."""
    tau = strength_for(law, robot.pre_pressure, robot.pad_area, est.adhesion)
    return preset_block(surface, source, est.mu, tau, pull_off)


def law_of(on: Bench) -> BondLaw:
    """The bond law of ``on``'s surface at the acquisition's contact smoothing."""
    return BondLaw.from_surface(on.surface, on.acquire.solver.contact_smoothing)


def quasi_static_block(on: Bench, est: Estimate, simulated: bool) -> dict[str, Any]:
    """The report's F_adh,0 block: the estimate taken back to no rate through the preset's rate
    law at the protocol's speed (a log is taken to follow `ftfof slip-test`'s protocol), beside
    the preset's F_adh,0 where the log is simulated."""
    law, robot = law_of(on), on.robot
    true = adhesion_truth(law, robot.pre_pressure, robot.pad_area) if simulated else None
    return {
        "estimate": quasi_static(law, est.adhesion, PROTOCOL.speed),
        "truth": true,
        "speed": PROTOCOL.speed,
    }


def rate_law_block(on: Bench, speeds: list[float]) -> dict[str, Any]:
    """The rate law's n and v* from simulated slip tests on ``on`` at two ``speeds``, F_adh,0
    taken as the preset's (:func:`rate_law`), beside the preset's n and v*."""
    law, robot = law_of(on), on.robot
    drags = {
        v: identify(simulated_log(on, replace(PROTOCOL, speed=v)))[1].final.adhesion for v in speeds
    }
    got = rate_law(law, adhesion_truth(law, robot.pre_pressure, robot.pad_area), drags)
    return {
        "speeds": sorted(drags),
        "adhesion": [drags[v] for v in sorted(drags)],
        "exponent": {"estimate": got.exponent, "truth": law.rate_exponent},
        "rate_speed": {"estimate": got.speed, "truth": law.rate_speed},
    }


def preset_of(
    on: Bench, source: str, est: Estimate, pull_off: float | None = None
) -> dict[str, Any]:
    """``on``'s surface preset with the identified mu and quasi-static F_adh,0 in ``est``
    (:func:`identified_preset`)."""
    return identified_preset(law_of(on), on.robot, on.surface, source, est, pull_off)
