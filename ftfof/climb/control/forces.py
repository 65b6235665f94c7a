"""The stance feet's contact forces each control step: climbing_slip §2.2.3's dynamic-level QP,
reduced to the forces of our sagittal robot.

Frame and signs (the wall frame of :mod:`ftfof.climb`: x up the wall, z out of it, gravity -x):

- ``f_i = (f_t, f_n)`` is the force the wall exerts on stance foot i through its pad, the pad's
  adhesion included: f_t along +x (up the wall), f_n along +z, so **f_n > 0 presses the foot into
  the wall** and f_n < 0 is the pad pulling on it (:mod:`ftfof.identify.estimate`'s F_n, the
  loop's ``force`` channel negated: that one is the pad's force on the wall, tension positive).
- The trunk wrench ``(Fx, Fz, My)`` is the feet's total force and their moment about the CoM,
  My = r_x f_n - r_z f_t with r the foot's contact point minus the CoM: positive My turns +x
  toward +z, the trunk's pitch sense in :mod:`ftfof.climb.model`.
- The joint torques that hold a foot's force are ``tau_i = -J_i^T f_i`` (statics: the servo
  balances the wall's generalised force J^T f; the legs' own weight is left out).

Our reading of §2.2.3: the paper's QP runs over the joint accelerations, the reaction forces and
the contact accelerations under the full dynamics. Here the legs are massless and the stance
feet fixed (the loop's joint PD tracks the motion, §5 handles slip), so what is left is the
trunk's Newton-Euler equation A f = w, kept as the soft term ||A f - w||^2_{W_w} (the paper's
W_qddot lets the floating base deviate), the reaction force term with the paper's W_rf as per-foot
diagonal weights, the contact wrench cones and the torque limits. §2.2.1 splits the reaction
F_r = F_c + F_m into contact and magnetic force and weighs F_c. A magnet's F_m is a force that is
always there; a pad's adhesion is a capacity, so the weight acts on f_i itself. Weighed from the
pyramid's apex, f_i + (0, F_adh,i), the cost pulled every foot toward f_n = -F_adh: on a wall the
feet's normal forces sum to about zero, so while the weights are equal that costs nothing, but
once §5 lowered a slipping fore foot's normal weight the QP pressed it +7 N and pulled its
partner to its pull-off (MST-M3F, F_adh 34.7 N: FL -10.4 N; with the weights on f_i, -0.5 N to
+0.2 N, issue 40).

Per stance foot, with its own mu, F_adh and pull-off P: |f_t| <= mu (f_n + F_adh), f_n >= -P, and
for each joint |J_i^T f_i| <= tau_max (a joint without a servo limit has tau_max = inf). F_adh is
the pad's shear capacity seen as extra normal load (s tau_max A / mu, about 35 N on acrylic); the
pad's normal pull is another capacity, its normal strength s sigma A (about 10 N), so the pyramid
is cut at P rather than at its apex.

The solver (proxsuite's dense ProxQP) sees the wrench error as three slack variables s with the
equality A f - s = w, and minimises s^T W_w s + sum_i c_i^T W_f,i c_i: the same QP, but with a
diagonal Hessian. Written as f^T (A^T W_w A + W_f) f its eigenvalues lie 1e9 apart (W_w ~ 1e6 to
track the wrench, the normal weight ~ 1e-3) and ProxQP split the normal load 0.2 N off the
optimum, or ran out of iterations.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np
from numpy.typing import NDArray
from proxsuite import proxqp

Array = NDArray[np.float64]
WRENCH_WEIGHT = (1e6, 1e6, 1e8)  # W_w on (Fx, Fz, My): a 0.1 N m moment error weighs as 1 N
TOLERANCE = 1e-9  # proxsuite's eps_abs on the primal and dual residuals
MAX_ITERATIONS = 500  # a solved step takes a few; proxsuite's infeasibility test rarely fires


class Status(StrEnum):
    """How a step's solve ended."""

    SOLVED = "solved"
    INFEASIBLE = "infeasible"  # no force met every cone and torque limit within the iterations
    FAILED = "failed"  # the solver stopped for another reason (dual infeasible, not run)


@dataclass(frozen=True)
class Stance:
    """The stance feet of one control step, each with its pad's parameters and its QP weights."""

    offset: Array  # (n, 2) contact point minus CoM (x, z), m
    jacobian: Array  # (n, 2, 3) d(contact x, z)/d(joint angles), wall frame, at the current angles
    friction: Array  # (n,) mu
    adhesion: Array  # (n,) F_adh, N (negative: a pad that must be pressed to hold)
    torque_limit: Array  # (n, 3) N m; inf for a joint without a servo limit
    weight: Array  # (n, 2) W_f's diagonal: tangential, normal
    pull_off: Array  # (n,) the most the pad may pull on its foot, N (f_n >= -pull_off)

    def __post_init__(self) -> None:
        n = len(self.offset)
        if n == 0:
            raise ValueError("a stance needs at least one foot")
        shapes = {
            "offset": (n, 2),
            "jacobian": (n, 2, 3),
            "friction": (n,),
            "adhesion": (n,),
            "torque_limit": (n, 3),
            "weight": (n, 2),
            "pull_off": (n,),
        }
        for name, shape in shapes.items():
            value = np.asarray(getattr(self, name), dtype=float)
            if value.shape != shape:
                raise ValueError(f"stance {name} has shape {value.shape}, expected {shape}")
            finite = np.isfinite(value) | ((name == "torque_limit") & (value == np.inf))
            if not finite.all():
                raise ValueError(f"stance {name} is not finite: {value}")
            object.__setattr__(self, name, value)
        if (self.friction < 0).any() or (self.torque_limit < 0).any() or (self.weight < 0).any():
            raise ValueError("friction, torque limits and weights must be non-negative")

    @property
    def size(self) -> int:
        return len(self.offset)


@dataclass(frozen=True)
class Distribution:
    """One step's answer: forces and torques are NaN unless the solve succeeded."""

    forces: Array  # (n, 2) f_t, f_n per stance foot, N
    torques: Array  # (n, 3) -J^T f, N m
    residual: Array  # (3,) A f - w: the wrench the forces miss
    status: Status
    iterations: int

    @property
    def solved(self) -> bool:
        return self.status is Status.SOLVED

    @classmethod
    def unsolved(cls, feet: int, status: Status, iterations: int) -> Distribution:
        """NaN everywhere, so that no caller drives a servo with a failed step's numbers."""
        forces, torques, residual = (np.full(shape, np.nan) for shape in ((feet, 2), (feet, 3), 3))
        return cls(forces, torques, residual, status, iterations)


def wrench_map(offset: Array) -> Array:
    """A (3 x 2n): the stance forces, interleaved (f_t, f_n) per foot, to the trunk wrench."""
    n = len(offset)
    A = np.zeros((3, 2 * n))
    A[0, 0::2] = 1.0
    A[1, 1::2] = 1.0
    A[2, 0::2] = -offset[:, 1]
    A[2, 1::2] = offset[:, 0]
    return A


def cone_rows(friction: Array, adhesion: Array, pull_off: Array) -> tuple[Array, Array]:
    """Rows C f <= u of each foot's adhesion-shifted pyramid: friction up, down, pull-off."""
    n = len(friction)
    C = np.zeros((3 * n, 2 * n))
    u = np.zeros(3 * n)
    for i, (mu, grip, pull) in enumerate(zip(friction, adhesion, pull_off, strict=True)):
        rows, cols = slice(3 * i, 3 * i + 3), slice(2 * i, 2 * i + 2)
        C[rows, cols] = [[1.0, -mu], [-1.0, -mu], [0.0, -1.0]]
        u[rows] = [mu * grip, mu * grip, pull]
    return C, u


def torque_rows(jacobian: Array) -> Array:
    """Rows J_i^T f_i of every joint: block diagonal over the feet."""
    n = len(jacobian)
    C = np.zeros((3 * n, 2 * n))
    for i, J in enumerate(jacobian):
        C[3 * i : 3 * i + 3, 2 * i : 2 * i + 2] = J.T
    return C


def constraints(stance: Stance) -> tuple[Array, Array, Array]:
    """C, l, u with l <= C x <= u over x = (f, s): the pyramids, then the torque limits."""
    cone, upper = cone_rows(stance.friction, stance.adhesion, stance.pull_off)
    limit = stance.torque_limit.ravel()
    C = np.vstack([cone, torque_rows(stance.jacobian)])
    C = np.hstack([C, np.zeros((len(C), 3))])  # the slack is free
    lower = np.concatenate([np.full(len(upper), -np.inf), -limit])
    return C, lower, np.concatenate([upper, limit])


def cost(stance: Stance, wrench_weight: Array) -> tuple[Array, Array]:
    """H, g of 1/2 x^T H x + g^T x = s^T W_w s + sum_i f_i^T W_f,i f_i over x = (f, s)."""
    H = np.diag(2.0 * np.concatenate([stance.weight.ravel(), wrench_weight]))
    return H, np.zeros(len(H))


def tracking(stance: Stance) -> Array:
    """The equality A f - s = w that defines the slack s as the wrench the forces miss."""
    return np.hstack([wrench_map(stance.offset), -np.eye(3)])


def _status(info: proxqp.Info) -> Status:
    """proxsuite's verdict in ours: a run that ends at the iteration cap with its constraints
    still broken is infeasible (its own infeasibility test seldom fires on problems this small)."""
    if info.status == proxqp.PROXQP_SOLVED:
        return Status.SOLVED
    infeasible = info.status == proxqp.PROXQP_PRIMAL_INFEASIBLE or (
        info.status == proxqp.PROXQP_MAX_ITER_REACHED and info.pri_res > TOLERANCE
    )
    return Status.INFEASIBLE if infeasible else Status.FAILED


@dataclass
class ForceDistributor:
    """The QP solver kept between control steps: a step with as many stance feet as the last
    updates its matrices and starts from the last solution; a change of stance builds anew."""

    wrench_weight: Array = field(default_factory=lambda: np.array(WRENCH_WEIGHT))
    _qp: proxqp.dense.QP | None = field(default=None, init=False, repr=False)

    def reset(self) -> None:
        """Forget the solver: the next step starts cold (a new phase, or a timing baseline)."""
        self._qp = None

    def solve(self, stance: Stance, wrench: Array) -> Distribution:
        """The forces that best give the trunk ``wrench`` (Fx, Fz, My about the CoM, N and N m)
        inside every pyramid and torque limit."""
        wrench = np.asarray(wrench, dtype=float)
        if wrench.shape != (3,) or not np.isfinite(wrench).all():
            raise ValueError(f"the wrench must be 3 finite numbers, got {wrench}")
        H, g = cost(stance, np.asarray(self.wrench_weight, dtype=float))
        A = tracking(stance)
        C, lower, upper = constraints(stance)
        qp = self._qp
        if qp is None or qp.model.dim != len(g):
            qp = self._build(H, g, A, wrench, C, lower, upper)
        else:
            qp.update(H=H, g=g, A=A, b=wrench, C=C, l=lower, u=upper)
        qp.solve()
        return self._result(qp, stance, wrench)

    def _build(
        self, H: Array, g: Array, A: Array, b: Array, C: Array, lower: Array, upper: Array
    ) -> proxqp.dense.QP:
        qp = proxqp.dense.QP(len(g), len(b), len(C))
        qp.settings.eps_abs = TOLERANCE
        qp.settings.eps_rel = 0.0
        qp.settings.max_iter = MAX_ITERATIONS
        qp.settings.initial_guess = proxqp.WARM_START_WITH_PREVIOUS_RESULT
        qp.init(H, g, A, b, C, lower, upper)
        self._qp = qp
        return qp

    def _result(self, qp: proxqp.dense.QP, stance: Stance, wrench: Array) -> Distribution:
        """The step's answer; a failed solve leaves no solver behind to warm-start from."""
        status = _status(qp.results.info)
        iterations = int(qp.results.info.iter)
        n = stance.size
        if status is not Status.SOLVED:
            self._qp = None
            return Distribution.unsolved(n, status, iterations)
        forces = qp.results.x[: 2 * n].reshape(n, 2).copy()
        torques = -np.einsum("nij,ni->nj", stance.jacobian, forces)
        residual = wrench_map(stance.offset) @ forces.ravel() - wrench
        return Distribution(forces, torques, residual, status, iterations)
