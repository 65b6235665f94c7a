"""A compiled float32 GRU layer for whole populations: the optimiser's hot path.

One call runs a layer over (batch, steps), input projections included (a precomputed (B, T, 3H)
projection costs more in memory traffic than the multiply-adds it saves); the last layer has its
linear K-output head fused so its hidden states are never stored. The recurrence works on blocks
of four sequences so each recurrent weight loaded from cache feeds four multiply-adds, and blocks
run in parallel threads. Gates use a rational tanh (sigmoid(x) = (1 + tanh(x/2)) / 2) so the gate
loop vectorises instead of calling libm per element.

The tanh approximation x P(x^2) / Q(x^2) (degrees 4/4 in x^2) was fitted by iteratively
reweighted least squares on [0, 9] and is clamped there; its error against tanh is below 6e-8
in float64 and 4e-7 in float32, below the resolution of the float32 weights it is used with.
Q has positive coefficients, so it has no poles on the real line.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
from numpy.typing import NDArray

_F = np.float32
_P = tuple(
    _F(c)
    for c in (
        0.9999999230784795,
        0.13384777259462982,
        0.0035002799050022136,
        2.069519322704027e-05,
        1.3490046129660199e-08,
    )
)
_Q = tuple(
    _F(c)
    for c in (
        1.0,
        0.46718080261405104,
        0.025894230461243655,
        0.0003293697255197393,
        7.828602008589243e-07,
    )
)
_CLAMP = _F(9.0)
_HALF = _F(0.5)
_ONE = _F(1.0)
BLOCK = 4  # sequences per register block in the recurrence
_KERNEL = {"fastmath": {"contract"}, "error_model": "numpy", "cache": True}


@numba.njit(inline="always", **_KERNEL)
def tanh_rational(x):  # pragma: no cover - compiled
    a = min(max(x, -_CLAMP), _CLAMP)
    s = a * a
    p = _P[0] + s * (_P[1] + s * (_P[2] + s * (_P[3] + s * _P[4])))
    q = _Q[0] + s * (_Q[1] + s * (_Q[2] + s * (_Q[3] + s * _Q[4])))
    return a * p / q


@numba.njit(inline="always", **_KERNEL)
def gru_cell(a_r, a_z, a_in, a_hn, h):  # pragma: no cover - compiled
    """PyTorch's GRU cell for one unit, from its gates' pre-activations: a_r and a_z (input and
    recurrent parts summed), a_in and a_hn (the n gate's input part and W_hn h + b_hn). Returns
    r, z, n and the new state; the one home of these equations for inference and training."""
    r = _HALF + _HALF * tanh_rational(_HALF * a_r)
    z = _HALF + _HALF * tanh_rational(_HALF * a_z)
    n = tanh_rational(a_in + r * a_hn)
    return r, z, n, (_ONE - z) * n + z * h


@numba.njit(**_KERNEL)
def tanh_array(x, out):  # pragma: no cover - compiled
    for i in range(x.size):
        out[i] = tanh_rational(x[i])


@numba.njit(inline="always", **_KERNEL)
def _advance(x, t, first, rows, w_ih_t, b_ih, w_hh_t, b_hh, h, gi, gh):  # pragma: no cover
    """One time step of PyTorch's GRU (gates r, z, n) for a block of sequences, h in place."""
    inputs = x.shape[2]
    width = b_hh.shape[0]
    hid = width // 3
    for i in range(BLOCK):
        gi[i, :] = b_ih
        gh[i, :] = b_hh
    for i in range(rows):
        for k in range(inputs):
            xk = x[first + i, t, k]
            for j in range(width):
                gi[i, j] += xk * w_ih_t[k, j]
    for k in range(hid):  # each recurrent weight feeds the four rows of the block
        h0 = h[0, k]
        h1 = h[1, k]
        h2 = h[2, k]
        h3 = h[3, k]
        for j in range(width):
            w = w_hh_t[k, j]
            gh[0, j] += h0 * w
            gh[1, j] += h1 * w
            gh[2, j] += h2 * w
            gh[3, j] += h3 * w
    for i in range(rows):
        for j in range(hid):
            h[i, j] = gru_cell(
                gi[i, j] + gh[i, j],
                gi[i, hid + j] + gh[i, hid + j],
                gi[i, 2 * hid + j],
                gh[i, 2 * hid + j],
                h[i, j],
            )[3]


@numba.njit(parallel=True, **_KERNEL)
def gru_run(x, w_ih_t, b_ih, w_hh_t, b_hh, out, head_w, head_b, y, fused):  # pragma: no cover
    """One layer from h0 = 0 over x (B, T, I), weights transposed.

    ``fused``: only the linear head y (B, T, K) = head_w (K, H) . h_t + head_b is written (the
    last layer); otherwise the hidden states go to ``out`` (B, T, H) for the next layer.
    """
    n_seq, steps, _ = x.shape
    width = b_hh.shape[0]
    hid = width // 3
    n_out = head_b.shape[0]
    for block in numba.prange((n_seq + BLOCK - 1) // BLOCK):
        first = block * BLOCK
        rows = min(BLOCK, n_seq - first)
        h = np.zeros((BLOCK, hid), np.float32)
        gi = np.empty((BLOCK, width), np.float32)
        gh = np.empty((BLOCK, width), np.float32)
        for t in range(steps):
            _advance(x, t, first, rows, w_ih_t, b_ih, w_hh_t, b_hh, h, gi, gh)
            for i in range(rows):
                if fused:
                    for o in range(n_out):
                        acc = head_b[o]
                        for j in range(hid):
                            acc += head_w[o, j] * h[i, j]
                        y[first + i, t, o] = acc
                else:
                    out[first + i, t, :] = h[i, :]


@dataclass(frozen=True)
class Layer:
    """One GRU layer's float32 weights laid out for the kernels (W_ih and W_hh transposed)."""

    w_ih_t: NDArray[np.float32]  # (inputs, 3H)
    b_ih: NDArray[np.float32]
    w_hh_t: NDArray[np.float32]  # (H, 3H)
    b_hh: NDArray[np.float32]

    @classmethod
    def from_torch(cls, w_ih: NDArray, w_hh: NDArray, b_ih: NDArray, b_hh: NDArray) -> Layer:
        f32 = np.float32
        return cls(
            np.ascontiguousarray(np.asarray(w_ih, f32).T),
            np.ascontiguousarray(b_ih, f32),
            np.ascontiguousarray(np.asarray(w_hh, f32).T),
            np.ascontiguousarray(b_hh, f32),
        )

    @property
    def hidden(self) -> int:
        return self.w_hh_t.shape[0]

    def hidden_states(self, seq: NDArray[np.float32]) -> NDArray[np.float32]:
        """(B, T, inputs) -> (B, T, H)."""
        out = np.empty((*seq.shape[:2], self.hidden), np.float32)
        unused_w, unused_b = np.zeros((1, self.hidden), np.float32), np.zeros(1, np.float32)
        self._run(seq, out, unused_w, unused_b, np.empty((1, 1, 1), np.float32), False)
        return out

    def head(
        self, seq: NDArray[np.float32], w: NDArray[np.float32], b: NDArray[np.float32]
    ) -> NDArray:
        """(B, T, inputs) -> (B, T, K) linear head (w (K, H), b (K,)) over the hidden states."""
        y = np.empty((*seq.shape[:2], len(b)), np.float32)
        self._run(seq, np.empty((1, 1, 1), np.float32), w, b, y, True)
        return y

    def _run(self, seq, out, head_w, head_b, y, fused: bool) -> None:
        gru_run(seq, self.w_ih_t, self.b_ih, self.w_hh_t, self.b_hh, out, head_w, head_b, y, fused)
