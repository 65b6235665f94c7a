"""Building simulation specs for tests: presets with a few values changed, simple motions."""

from __future__ import annotations

import numpy as np

from ftfof.config import Params, Robot
from ftfof.sim.spec import Bench, SampleSpec
from ftfof.trajectory.bezier import Samples
from ftfof.trajectory.piecewise import PiecewiseQuintic

PUBLISHED = (
    np.array([2.3, 18.3, 31.4, 108.8, 123.7, 124.5, 23.6, 25.5, 29.0, 48.6, 30.5, 11.1]) / 1000
)

# The grip foot (foot.model: grip, docs/decisions/0028): the film's first grip_length clamped, the
# rest of the pad free ahead of it, on the old spring-loaded ankle. The physics tests of the bond
# law and of the film's own elastica (Kendall's peel, pull-off, lap shear, the clamp-edge bend)
# need a free film; the plate foot backs the whole film and turns it about its toe instead.
GRIP = {
    "model": "grip",
    "backing": None,
    "ankle_range": None,
    "ankle_stiffness": 0.5,
    "ankle_damping": 0.005,
    "inertia": 1.0e-5,
}

# Acrylic as calibrated on the grip foot before the plate (params.yaml at a168eba, decision 0013's
# cap on G): for the grip tests whose expectations are the elastica of that film on that bond
ACRYLIC_ON_GRIP = {"strength": 32711.3, "fracture_energy": 76.8, "preload_pressure": 13035.8}


def grip_robot(robot: Robot, **foot: object) -> Robot:
    """``robot`` with the grip foot on its platform (``foot``: more of the foot's fields)."""
    platform = robot.platform
    grip = platform.foot.model_copy(update={**GRIP, **foot})
    return robot.model_copy(update={"platform": platform.model_copy(update={"foot": grip})})


def bench(
    params: Params,
    surface: dict | None = None,
    foot: dict | None = None,
    robot: dict | None = None,
    solver: dict | None = None,
    leg_model: str = "lumped",
    film: dict | None = None,
) -> Bench:
    r = params.selected_robot
    mech = r.platform.model_copy(
        update={
            "foot": r.platform.foot.model_copy(update=foot or {}),
            "film": r.platform.film.model_copy(update=film or {}),
        }
    )
    r = r.model_copy(update={"platform": mech, **(robot or {})})
    settings = dict(solver or {})
    if "nodes" in settings:  # a film of N elements is uniform, whatever params grade (today: none)
        settings.setdefault("edge_element", None)
    acquire = params.acquire.model_copy(
        update={
            "solver": params.acquire.solver.model_copy(update=settings),
            "leg_model": leg_model,
        }
    )
    s = params.selected_surface.model_copy(update=surface or {})
    return Bench(r, s, params.platform, acquire, params.base.seed)


def waypoints(
    t: list[float], p: list[tuple[float, float]], v: list[tuple[float, float]]
) -> PiecewiseQuintic:
    """A piecewise quintic through positions and velocities at times (zero accelerations)."""
    pos = np.array(p, dtype=float)[None]
    vel = np.array(v, dtype=float)[None]
    return PiecewiseQuintic.from_samples(
        Samples(np.array(t, dtype=float), pos, vel, np.zeros_like(pos))
    )


def straight_pull(
    angle_deg: float, speed: float, duration: float, ramp: float = 0.05
) -> PiecewiseQuintic:
    """At rest, then up to ``speed`` along ``angle_deg`` (from +x) over ``ramp``, then steady."""
    d = np.array([np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))])
    t = [0.0, ramp, duration]
    s_ramp = speed * ramp / 2
    return waypoints(
        t,
        [(0, 0), tuple(d * s_ramp), tuple(d * (s_ramp + speed * (duration - ramp)))],
        [(0, 0), tuple(d * speed), tuple(d * speed)],
    )


def with_trajectory(b: Bench, traj: PiecewiseQuintic, key: str = "test") -> SampleSpec:
    return b.spec(key, 0, traj)
