"""The adhesive interface: one cohesive bond per film node (docs/simulator.md).

Force law (evaluated in C++ as a symbolic user function, see :mod:`ftfof.sim.pad`), per node
with opening u_n (film above plate), slip u_t from the bond's anchor and pad area A:

- bonded: f = s A (K_t u_t, K u_n) — linear springs through zero whose stiffness is scaled by
  s = phi * R * (1 - D): the preload factor phi = 1 - exp(-p_max / p*) of the peak contact
  pressure seen while bonded, the rate factor R = max over the current loading of
  1 + (v / v*)^n, v the rate of the *mixed-mode* opening (normal and shear alike, each relative
  to its own critical opening) low-passed over RATE_FILTER seconds (so the snap of a
  neighbour's release does not count as loading rate), and the damage D of the softening
  branch; all three are history variables, so Newton sees a constant law within each step;
- every node: unilateral contact with a C1 ramp of width w (stiffness rises 0 -> Kc A over w)
  and Hunt-Crossley damping; broken nodes in contact get Coulomb friction mu * N (regularised).

Each mode is bilinear (elastic, then linear softening) and energy-consistent: mode I has the
strength sigma, the critical opening d_n = 2 G / sigma and the elastic stiffness
K = sigma / (r d_n); mode II has tau = k sigma (k: the surface's lap-shear to pull-off ratio),
G_II and d_t = 2 G_II / tau, K_t = tau / (r d_t). The elastic fraction r = sigma / (Kc d_n) makes
the bond as stiff in tension as the adhesive layer is in compression (r = 1, a brittle law, if
the layer is softer than that). With the mixed-mode opening
lambda = sqrt((max(u_n, 0) / d_n)^2 + (u_t / d_t')^2), the bond is elastic up to lambda = r,
softens with the secant factor 1 - D = r (1 - lambda_max) / (lambda_max (1 - r)) beyond, and
breaks at lambda = 1; each mode then has released exactly its fracture energy, and with
G_II = G a mixed-mode opening releases G whatever its mixity (Kendall's peel needs one G).
Under compression p the shear allowance grows by the friction the pressure adds
(adhesion-offset Coulomb: |tau| <= s tau_max + mu p), d_t' = d_t (1 + mu p / (s tau)), so a
pressed pad does not shear off at its bare bond strength.
A broken node pressed above the re-bond pressure forms a new bond anchored where it lies.

:func:`step` is the per-time-step state machine the simulator's pre-step calls: it reads node
states, updates the bond state in place and lists the bonds whose connector parameters must be
pushed. Compiled, it costs about a microsecond for 20 nodes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeVar

import numba
import numpy as np
from numpy.typing import NDArray

import ftfof.config as config

Array = NDArray[np.float64]

BREAK, SCALE, REBOND = 1, 2, 3
PUSH_STEP = 0.02  # push a scale once the traction would be off by this fraction of the strength
RATE_FILTER = 0.01  # s, time constant of the opening-rate low-pass
LOADED = 0.05  # a bond counts as loaded (its rate history grows) above this lambda / r
# a broken node this far above the plate (m), and not closing faster than it can cover in
# IDLE_STEPS steps, has its connector switched off (:func:`idle_changes`)
IDLE_HEIGHT = 1.0e-3
IDLE_STEPS = 4.0


@dataclass(frozen=True)
class BondLaw:
    """The per-area constants of the law for one surface."""

    critical_opening: float  # d_n = 2 G / sigma, m
    elastic_fraction: float  # r: softening starts at lambda = r
    stiffness: float  # K = sigma / (r d_n), Pa/m
    shear_opening: float  # d_t = 2 G_II / tau, m
    shear_strength: float  # tau = k sigma, Pa
    shear_stiffness: float  # K_t = tau / (r d_t), Pa/m
    contact_stiffness: float  # Pa/m
    contact_smoothing: float  # w, m
    hunt_crossley: float  # 1.5 (1 - e) / v_ref, s/m
    friction: float
    friction_speed: float  # regularisation of Coulomb friction, m/s
    rate_exponent: float
    rate_speed: float
    preload_pressure: float
    rebond_pressure: float

    @classmethod
    def from_surface(cls, surface: config.Surface, smoothing: float) -> BondLaw:
        sigma, G = surface.strength, surface.fracture_energy
        tau, G_II = sigma * surface.shear_capacity_ratio, G * surface.shear_energy_ratio
        d_n, d_t = 2 * G / sigma, 2 * G_II / tau
        r = min(sigma / (surface.contact_stiffness * d_n), 1.0)
        return cls(
            critical_opening=d_n,
            elastic_fraction=r,
            stiffness=sigma / (r * d_n),
            shear_opening=d_t,
            shear_strength=tau,
            shear_stiffness=tau / (r * d_t),
            contact_stiffness=surface.contact_stiffness,
            contact_smoothing=smoothing,
            hunt_crossley=1.5 * (1 - surface.restitution) / 0.1,
            friction=surface.friction,
            friction_speed=1e-3,
            rate_exponent=surface.rate_exponent,
            rate_speed=surface.rate_speed,
            preload_pressure=surface.preload_pressure,
            rebond_pressure=surface.rebond_pressure,
        )

    def preload_factor(self, pressure: Array | float) -> Array:
        return preload_factor(np.asarray(pressure), self.preload_pressure)

    def contact_pressure(self, opening: Array, opening_rate: Array) -> Array:
        """:func:`contact_pressure` on arrays, with this surface's constants."""
        return contact_pressure(
            np.asarray(opening, dtype=float),
            np.asarray(opening_rate, dtype=float),
            self.contact_stiffness,
            self.contact_smoothing,
            self.hunt_crossley,
            np.maximum,
            np.minimum,
        )


# The law's formulas, each written once and evaluated by numpy on arrays and by the compiled
# :func:`step` on scalars. The contact law is also the bond connector's symbolic user function
# (:mod:`ftfof.sim.pad`), evaluated on Exudyn symbolic reals that neither numpy nor compiled
# code can take: so it is plain arithmetic, with max / min given by the caller.

Value = TypeVar("Value")  # a float, a numpy array or an Exudyn symbolic Real
Clip = Callable[[Value, float], Value]  # max or min against a constant, in the caller's kind


def contact_pressure(
    opening: Value,
    opening_rate: Value,
    stiffness: Value | float,
    smoothing: float,
    damping: float,
    maximum: Clip[Value],
    minimum: Clip[Value],
) -> Value:
    """Unilateral contact: a C1 ramp of width w (stiffness rising 0 -> Kc over w) times the
    Hunt-Crossley factor max(1 - hc v, 0); pressure with Kc per area, force with Kc A."""
    pen = maximum(-opening, 0.0)
    ramp = minimum(pen, smoothing)
    squeeze = ramp * ramp / (2 * smoothing) + maximum(pen - smoothing, 0.0)
    return stiffness * squeeze * maximum(1.0 - damping * opening_rate, 0.0)


def preload_factor(pressure: Value, preload_pressure: float) -> Value:
    """phi = 1 - exp(-p / p*) of the peak contact pressure p seen while bonded."""
    return 1.0 - np.exp(-pressure / preload_pressure)


# compiled forms for :func:`step` (same source file, so an edit invalidates its cache)
_contact_pressure = numba.njit(contact_pressure)
_preload_factor = numba.njit(preload_factor)


@numba.njit
def _max(a: float, b: float) -> float:
    return max(a, b)


@numba.njit
def _min(a: float, b: float) -> float:
    return min(a, b)


@dataclass
class BondState:
    """Mutable per-node state: anchors in the plate frame, broken flags, preload history."""

    anchor: Array  # x of the bond point on the plate, m
    broken: NDArray[np.bool_]
    p_max: Array  # peak contact pressure while bonded, Pa
    rate: Array  # rate factor history R of the current loading
    scale: Array  # phi * R * (1 - D) as last pushed to the connector
    opening_rate: Array  # low-passed opening rate, m/s
    opening_max: Array  # peak mixed-mode opening lambda of the bond (its damage)

    @classmethod
    def bonded(cls, x: Array, initial_pressure: float, law: BondLaw) -> BondState:
        n = len(x)
        p = np.full(n, initial_pressure)
        return cls(
            x.astype(float).copy(),
            np.zeros(n, bool),
            p,
            np.ones(n),
            law.preload_factor(p),
            np.zeros(n),
            np.zeros(n),
        )


@numba.njit(cache=True)
def step(
    q: Array,
    qd: Array,
    node_index: NDArray[np.int64],
    plate_index: int,
    x_ref: Array,
    area: Array,
    anchor: Array,
    broken: NDArray[np.bool_],
    p_max: Array,
    rate: Array,
    scale: Array,
    opening_rate: Array,
    opening_max: Array,
    h: float,
    law: tuple[float, ...],
    push: NDArray[np.int64],
    kind: NDArray[np.int64],
) -> tuple[int, int, float, float]:  # pragma: no cover - compiled
    """One pre-step update.

    Returns (pushes, bonded count, lowest film height, largest bond load: the opening lambda / r,
    1 once a bond softens); the last tells the step control how close the next bond failure is.
    """
    d_c, d_t, tau, r, mu, kc, w, hc, p_star, p_rebond, n_rate, v_star, push_step = law
    n = node_index.size
    n_push = 0
    n_bonded = 0
    lam_max = 0.0
    lowest = np.inf
    xp, zp = q[plate_index], q[plate_index + 1]
    vxp, vzp = qd[plate_index], qd[plate_index + 1]
    for i in range(n):
        j = node_index[i]
        x = x_ref[i] + q[j]
        un = q[j + 1] - zp
        vn = qd[j + 1] - vzp
        lowest = min(lowest, un)
        pressure = _contact_pressure(un, vn, kc, w, hc, _max, _min)
        if not broken[i]:
            ut = x - xp - anchor[i]
            healthy = _preload_factor(p_max[i], p_star) * rate[i]  # phi * R
            d_shear = d_t * (1.0 + mu * pressure / (max(healthy, 1e-12) * tau))
            a_n, a_t = max(un, 0.0) / d_c, ut / d_shear
            lam = np.sqrt(a_n * a_n + a_t * a_t)
            if lam >= 1.0:
                broken[i] = True
                push[n_push] = i
                kind[n_push] = BREAK
                n_push += 1
                continue
            n_bonded += 1
            lam_max = max(lam_max, min(lam / r, 1.0))
            p_max[i] = max(p_max[i], pressure)
            # rate of the mixed-mode opening, in units of the normal critical opening per second
            vt = qd[j] - vxp
            if lam > 0.0:
                v_mixed = d_c * (a_n * vn / d_c + a_t * vt / d_shear) / lam
            else:
                v_mixed = max(vn, 0.0)
            opening_rate[i] += (v_mixed - opening_rate[i]) * min(h / RATE_FILTER, 1.0)
            if lam > LOADED * r and opening_rate[i] > 0.0:
                rate[i] = max(rate[i], 1.0 + (opening_rate[i] / v_star) ** n_rate)
            opening_max[i] = max(opening_max[i], lam)
            healthy = _preload_factor(p_max[i], p_star) * rate[i]
            target = healthy
            if opening_max[i] > r:  # softening branch: secant stiffness of the bilinear law
                target *= r * (1.0 - opening_max[i]) / (opening_max[i] * (1.0 - r))
            # push once the traction would be off by push_step of the bond's strength
            if abs(target - scale[i]) * max(lam / r, 1.0) > push_step * healthy:
                scale[i] = target
                push[n_push] = i
                kind[n_push] = SCALE
                n_push += 1
        elif pressure > p_rebond:
            broken[i] = False
            anchor[i] = x - xp
            p_max[i] = pressure
            rate[i] = 1.0
            opening_rate[i] = 0.0
            opening_max[i] = 0.0
            scale[i] = _preload_factor(pressure, p_star)
            push[n_push] = i
            kind[n_push] = REBOND
            n_push += 1
            n_bonded += 1
    return n_push, n_bonded, lowest, lam_max


@numba.njit(cache=True)
def idle_changes(
    q: Array,
    qd: Array,
    node_index: NDArray[np.int64],
    plate_index: int,
    broken: NDArray[np.bool_],
    idle: NDArray[np.bool_],
    h: float,
    changed: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """Mark idle the broken nodes well clear of the plate, wake those that come near; lists the
    nodes that changed in ``changed`` and returns how many.

    A broken node's connector pulls nothing while the node is above the plate (no bond, no
    contact: its force is exactly zero), yet the solver evaluates its user function on every
    Newton iteration; about half a run's cost is the bond connectors. Switching off the idle ones
    leaves every residual bit for bit as it was, as long as no idle node reaches the plate within
    a step: hence the height margin and the look-ahead at the node's approach speed.
    """
    n_changed = 0
    zp, vzp = q[plate_index + 1], qd[plate_index + 1]
    for i in range(node_index.size):
        j = node_index[i]
        closing = max(vzp - qd[j + 1], 0.0)
        clear = q[j + 1] - zp - IDLE_STEPS * closing * h > IDLE_HEIGHT
        now = broken[i] and clear
        if now != idle[i]:
            idle[i] = now
            changed[n_changed] = i
            n_changed += 1
    return n_changed


def kernel_law(law: BondLaw, push_step: float = PUSH_STEP) -> tuple[float, ...]:
    """The constants :func:`step` needs, in its order (area-independent)."""
    return (
        law.critical_opening,
        law.shear_opening,
        law.shear_strength,
        law.elastic_fraction,
        law.friction,
        law.contact_stiffness,
        law.contact_smoothing,
        law.hunt_crossley,
        law.preload_pressure,
        law.rebond_pressure,
        law.rate_exponent,
        law.rate_speed,
        push_step,
    )
