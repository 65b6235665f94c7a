"""A foot's pad that finds another surface mid-climb (``climb.surface_change``, issue 40).

From the switch on, the pad holds with the other surface's whole bond law (:mod:`ftfof.sim.bonds`):
its friction and adhesion capacity, with the stiffnesses and critical openings that go with them,
since one surface's strength without its openings is no surface at all. The pad keeps its bond
history (preload, rate and damage factors, each a fraction of the law's own strength), so a bond
that held on the old surface holds on the new one as far as the new law lets it: a weaker surface
can break it at once.

A pad's law lives in three places, and the switch sets all three, on that pad only: the
connectors' symbolic force law (the friction is baked into it), the connectors' stiffness
parameters (K_t A, K A, Kc A) and the pad tracker's kernel constants. The symbolic law is made
when the system is built, since it must exist before the solve. The other pads and the platform
never see any of it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import ftfof.config as config
from ftfof.config.stages import SurfaceChange
from ftfof.errors import ParamsError
from ftfof.sim import bonds
from ftfof.sim.pad import bond_law, bond_stiffness
from ftfof.sim.padstate import PadParts, PadTracker


@dataclass(frozen=True)
class SurfaceSwitch:
    """Which pad changes surface, when, and onto what."""

    leg: int  # index into ftfof.config.LEG_NAMES
    time: float  # s into the climb
    surface: config.Surface


def switch_of(
    change: SurfaceChange | None,
    surfaces: Mapping[str, config.Surface],
    end: float,
    key: str = "climb.surface_change",
) -> SurfaceSwitch | None:
    """A surface ``change`` resolved against the ``surfaces`` presets, for a climb that ends at
    ``end``; a switch outside (0, end) is a :class:`ParamsError` naming ``key``, the params entry
    the change came from (the foot and the preset are checked with the params)."""
    if change is None:
        return None
    if not 0.0 < change.time < end:
        raise ParamsError(
            f"{key}.time",
            f"{change.time:g} s is outside the climb, which runs (0, {end:g}) s",
        )
    return SurfaceSwitch(config.LEG_NAMES.index(change.foot), change.time, surfaces[change.surface])


def surface_at(
    switch: SurfaceSwitch | None, surface: config.Surface, leg: int, time: float
) -> config.Surface:
    """The preset ``leg``'s pad stands on at ``time``: the climb's ``surface``, or the switch's
    from its time on where it moves that pad."""
    if switch is not None and switch.leg == leg and time >= switch.time:
        return switch.surface
    return surface


class PadSwitch:
    """A switch armed in a built system: its law made with the system, applied once."""

    def __init__(self, mbs: Any, switch: SurfaceSwitch, law: bonds.BondLaw, parts: PadParts):
        self.switch, self.law, self.parts = switch, law, parts
        self.force_law = bond_law(mbs, law)  # must outlive the solve: the Climber keeps us
        self.done = False

    def apply(self, mbs: Any, tracker: PadTracker) -> None:
        """Put the pad on the new surface: its connectors' law and stiffnesses, its kernel."""
        setp = mbs.SetObjectParameter
        for obj, area in zip(self.parts.bonds, self.parts.area, strict=True):
            setp(obj, "stiffness", bond_stiffness(self.law, float(area)))
            setp(obj, "springForceUserFunction", self.force_law)
        tracker.kernel_law = bonds.kernel_law(self.law)
        self.done = True
