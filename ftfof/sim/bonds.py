"""The adhesive interface: one cohesive bond and one friction slider per film node
(docs/simulator.md, "Adhesive interface").

Force law (a symbolic user function evaluated in C++, :mod:`ftfof.sim.pad`), per node with
opening u_n (film above plate), slip u_t from the bond's anchor and pad area A:

- bonded: the cohesive bond f = s A (K_t u_t, K u_n), springs through zero scaled by
  s = phi * R * (1 - D): the preload factor phi = 1 - exp(-p_max / p*) of the peak contact
  pressure seen while bonded, the rate factor R = 1 + (v / v*)^n of the bond's current
  mixed-mode opening rate v (low-passed over RATE_FILTER seconds, so that a neighbour's snap is
  no loading rate), and the damage D of the softening branch; history variables, so Newton sees
  a constant law within each step;
- every node: unilateral contact, a C1 ramp of width w (stiffness 0 -> Kc A) with Hunt-Crossley
  damping; and, in contact, bonded or broken, friction from an elastic-plastic spring-slider,
  f = clip(k_t A (x - a_f), +-mu N), N the node's compressive force (the contact plus a pressed
  bond's spring), its anchor a_f moved by return mapping between steps: below mu N it sticks
  without creep. Friction takes no rate factor.

Each mode of the bond is bilinear and energy-consistent: mode I has the strength sigma, the
critical opening d_n = 2 G / sigma and the stiffness K = sigma / (r d_n); mode II has
tau = k sigma (k: the lap-shear to pull-off ratio), G_II, d_t = 2 G_II / tau and
K_t = tau / (r d_t). The elastic fraction r = sigma / (Kc d_n) makes the bond as stiff in
tension as the adhesive layer is in compression (r = 1, brittle, if the layer is softer). With
the mixed-mode opening lambda = sqrt((max(u_n, 0) / d_n)^2 + (u_t / d_t)^2) the bond is elastic
up to lambda = r, softens with the secant factor 1 - D = r (1 - lambda_max) / (lambda_max (1 - r))
beyond, and breaks at lambda = 1, each mode having released its fracture energy (with G_II = G,
G whatever the mixity: Kendall's peel needs one G). The bond breaks on its own opening; friction
beside it holds mu N, so a sliding pad follows F_t = mu F_n + F_adh with F_adh = R phi tau A.
A broken node pressed above the re-bond pressure re-bonds where it lies while its slider sticks.

:func:`step`, the pre-step's compiled state machine, updates the bond and slider states in
place and lists the connectors whose parameters must be pushed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import TypeVar

import numba
import numpy as np
from numpy.typing import NDArray

import ftfof.config as config
from ftfof.sim.idle import idle_changes as idle_changes  # callers still say bonds.idle_changes

Array = NDArray[np.float64]

# push flags, or-ed per node: the damping slots (broken, scale) and the offset slots (anchors)
BREAK, SCALE, REBOND, SLIDE = 1, 2, 4, 8
PUSH_STEP = 0.02  # push once a traction would be off by this fraction of its limit (_slider)
RATE_FILTER = 0.01  # s, time constant of the opening-rate low-pass
LOADED = 0.05  # the rate factor ramps in over lambda / r in [0, LOADED] (no step in the force)
STICK_SPEED = 1e-5  # m/s: a node sliding slower sticks and may re-bond (the stiction bound)


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
    friction: float  # mu
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
            rate_exponent=surface.rate_exponent,
            rate_speed=surface.rate_speed,
            preload_pressure=surface.preload_pressure,
            rebond_pressure=surface.rebond_pressure,
        )

    def preload_factor(self, pressure: Array | float) -> Array:
        return preload_factor(np.asarray(pressure), self.preload_pressure)

    def drag_rate_factor(self, speed: float) -> float:
        """R of a bond sheared at ``speed`` (m/s), as a steady drag shears the pad's bonds:
        its opening lambda grows at speed / d_t, which the rate law, whose v* is a speed of
        normal opening, reads as speed d_n / d_t."""
        v = speed * self.critical_opening / self.shear_opening
        return 1.0 + (v / self.rate_speed) ** self.rate_exponent

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
    """Mutable per-node state: anchors in the plate frame, broken flags, preload history and the
    friction sliders' anchors."""

    anchor: Array  # x of the bond point on the plate, m
    broken: NDArray[np.bool_]
    p_max: Array  # peak contact pressure while bonded, Pa
    rate: Array  # rate factor R of the current opening rate
    scale: Array  # phi * R * (1 - D) as last pushed to the connector
    opening_rate: Array  # low-passed opening rate, m/s
    opening_max: Array  # peak mixed-mode opening lambda of the bond (its damage)
    slider: Array  # the friction slider's anchor a_f on the plate, m
    slider_pushed: Array  # a_f as last pushed to the connector

    @classmethod
    def bonded(cls, x: Array, initial_pressure: float, law: BondLaw) -> BondState:
        n, x = len(x), x.astype(float)
        p, zero = np.full(n, initial_pressure), np.zeros(n)
        phi = law.preload_factor(p)
        return cls(x.copy(), np.zeros(n, bool), p, np.ones(n), phi, zero, zero.copy(), x, x.copy())

    def arrays(self) -> tuple[np.ndarray, ...]:
        """The state in :func:`step`'s argument order."""
        return tuple(getattr(self, f.name) for f in fields(self))


@numba.njit
def _slider(
    i: int,
    rel: float,
    normal: float,
    anchor: Array,
    pushed: Array,
    mu: float,
    kt: float,
    tol: float,
    floor: float,
    slack: float,
) -> tuple[bool, bool]:  # pragma: no cover - compiled
    """Return mapping of node i's friction slider at film x ``rel`` on the plate, pressed with
    ``normal`` (N), stiffness ``kt`` (N/m): (whether it sticks, whether its anchor must be
    pushed: the connector's friction would be off by more than ``tol`` of mu N plus ``floor``,
    N). It sticks while it slid less than ``slack`` (m) this step. A node not pressed carries
    no friction: its anchor follows it, unpushed (a landing node meets its pushed anchor for
    one step, at a small N).

    k_t = K_t A, the bond's (one layer shears): a node sticks within mu p / K_t (~1 um), inside
    the bond's elastic reach, so the pad holds mu F_n at its bonds' peak (Kc / 3 did not)."""
    limit = mu * normal
    if limit <= 0.0:
        anchor[i] = rel
        return False, False
    trial = kt * (rel - anchor[i])
    sticks = abs(trial) - limit <= kt * slack
    if abs(trial) > limit:
        anchor[i] = rel - np.sign(trial) * limit / kt
    return sticks, kt * abs(anchor[i] - pushed[i]) > tol * limit + floor


@numba.njit
def _bond(
    i: int,
    ut: float,
    un: float,
    vt: float,
    vn: float,
    pressure: float,
    h: float,
    law: tuple[float, ...],
    broken: NDArray[np.bool_],
    history: tuple[Array, Array, Array, Array, Array],
) -> tuple[int, float]:  # pragma: no cover - compiled
    """One bonded node's update: (push flags, its load lambda / r capped at 1; -1 if it broke).
    ``history``: p_max, rate, scale, opening_rate, opening_max, as in :class:`BondState`."""
    d_c, d_t, r, n_rate, v_star, p_star, push_step = law[:7]
    p_max, rate, scale, opening_rate, opening_max = history
    a_n, a_t = max(un, 0.0) / d_c, ut / d_t
    lam = np.sqrt(a_n * a_n + a_t * a_t)
    if lam >= 1.0:
        broken[i] = True
        return BREAK, -1.0
    p_max[i] = max(p_max[i], pressure)
    # rate of the mixed-mode opening, in units of the normal critical opening per second
    v_mixed = d_c * (a_n * vn / d_c + a_t * vt / d_t) / lam if lam > 0.0 else max(vn, 0.0)
    opening_rate[i] += (v_mixed - opening_rate[i]) * min(h / RATE_FILTER, 1.0)
    loaded = min(lam / (LOADED * r), 1.0)
    rate[i] = 1.0 + loaded * (max(opening_rate[i], 0.0) / v_star) ** n_rate
    opening_max[i] = max(opening_max[i], lam)
    healthy = _preload_factor(p_max[i], p_star) * rate[i]
    target = healthy
    if opening_max[i] > r:  # softening branch: secant stiffness of the bilinear law
        target *= r * (1.0 - opening_max[i]) / (opening_max[i] * (1.0 - r))
    load = min(lam / r, 1.0)
    # push once the traction would be off by push_step of the bond's strength
    if abs(target - scale[i]) * max(lam / r, 1.0) > push_step * healthy:
        scale[i] = target
        return SCALE, load
    return 0, load


@numba.njit
def _friction(
    i: int,
    rel: float,
    un: float,
    pressure: float,
    h: float,
    law: tuple[float, ...],
    broken: NDArray[np.bool_],
    scale: Array,
    area: Array,
    slider: Array,
    pushed: Array,
) -> tuple[bool, bool]:  # pragma: no cover - compiled
    """Node i's slider (:func:`_slider`) under the node's compressive force as the connector sees
    it, the contact plus a pressed bond: (whether it sticks, whether its anchor must be pushed)."""
    d_t, r, push_step, mu = law[1], law[2], law[6], law[7]
    p_rebond, k_n, k_t = law[11:]
    squeeze = 0.0 if broken[i] else scale[i] * k_n * max(-un, 0.0)
    normal = area[i] * (pressure + squeeze)
    # a slider may be off by push_step of mu N plus that of its bond's strength (tau = K_t r
    # d_t), or of a broken node's friction at the re-bond pressure
    held = mu * p_rebond if broken[i] else scale[i] * k_t * r * d_t
    floor, kt, slack = push_step * held * area[i], k_t * area[i], STICK_SPEED * h
    return _slider(i, rel, normal, slider, pushed, mu, kt, push_step, floor, slack)


@numba.njit
def _rebond(
    i: int,
    rel: float,
    pressure: float,
    p_star: float,
    anchor: Array,
    broken: NDArray[np.bool_],
    history: tuple[Array, Array, Array, Array, Array],
) -> None:  # pragma: no cover - compiled
    """A broken node bonds again where it lies, as a fresh bond pressed at ``pressure``."""
    p_max, rate, scale, opening_rate, opening_max = history
    broken[i] = False
    anchor[i] = rel
    p_max[i] = pressure
    rate[i] = 1.0
    opening_rate[i] = 0.0
    opening_max[i] = 0.0
    scale[i] = _preload_factor(pressure, p_star)


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
    slider: Array,
    slider_pushed: Array,
    h: float,
    law: tuple[float, ...],
    push: NDArray[np.int64],
    kind: NDArray[np.int64],
) -> tuple[int, int, float, float]:  # pragma: no cover - compiled
    """One pre-step update; lists each node with something to push once, its flags or-ed.

    Returns (pushes, bonded count, lowest film height, largest bond load: the opening lambda / r,
    1 once a bond softens); the last tells the step control how close the next bond failure is.
    """
    p_star, kc, w, hc, p_rebond = law[5], law[8], law[9], law[10], law[11]
    history = (p_max, rate, scale, opening_rate, opening_max)
    n_push = n_bonded = 0
    lam_max, lowest = 0.0, np.inf
    xp, zp = q[plate_index], q[plate_index + 1]
    vxp, vzp = qd[plate_index], qd[plate_index + 1]
    for i in range(node_index.size):
        j = node_index[i]
        rel = x_ref[i] + q[j] - xp
        un, vn = q[j + 1] - zp, qd[j + 1] - vzp
        lowest = min(lowest, un)
        pressure = _contact_pressure(un, vn, kc, w, hc, _max, _min)
        sticks, moved = _friction(
            i, rel, un, pressure, h, law, broken, scale, area, slider, slider_pushed
        )
        flags = SLIDE if moved else 0
        if not broken[i]:
            ut, vt = rel - anchor[i], qd[j] - vxp
            change, load = _bond(i, ut, un, vt, vn, pressure, h, law, broken, history)
            flags |= change
            if load >= 0.0:
                n_bonded += 1
                lam_max = max(lam_max, load)
        elif pressure > p_rebond and sticks:
            _rebond(i, rel, pressure, p_star, anchor, broken, history)
            flags |= REBOND
            n_bonded += 1
        if flags:
            if flags & SLIDE:
                slider_pushed[i] = slider[i]
            push[n_push] = i
            kind[n_push] = flags
            n_push += 1
    return n_push, n_bonded, lowest, lam_max


def kernel_law(law: BondLaw, push_step: float = PUSH_STEP) -> tuple[float, ...]:
    """The constants :func:`step` needs, in its order (area-independent)."""
    return (
        # the bond's (:func:`_bond`), then the contact's and the slider's
        law.critical_opening,
        law.shear_opening,
        law.elastic_fraction,
        law.rate_exponent,
        law.rate_speed,
        law.preload_pressure,
        push_step,
        law.friction,
        law.contact_stiffness,
        law.contact_smoothing,
        law.hunt_crossley,
        law.rebond_pressure,
        law.stiffness,
        law.shear_stiffness,  # the slider's k_t (:func:`_slider`): K_t r d_t = tau
    )
