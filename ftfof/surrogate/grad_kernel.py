"""Compiled forward and backward passes of a GRU layer and a linear layer, for training.

Why not torch's own: its CPU GRU and Linear multiply through MKL, which picks its kernels by the
CPU's vendor as well as its instruction set, so the same dataset trained other weights on an AMD
and an Intel machine (MKL documents bit-identical results across Intel processors only). These
loops are compiled by numba for one pinned target (``stages.runtime``) and sum in one fixed
order, so a layer gives the same bits on any x86-64 CPU:

- every output element is one loop's sum, in the order of its terms;
- the weight gradients sum over (batch, step) rows in row order;
- the cell is the population kernel's (:func:`ftfof.surrogate.gru_kernel.gru_cell`, its rational
  tanh included), so a trained model is evaluated during the search by the function it was
  fitted with.

Layouts follow torch: gates (r, z, n) side by side in 3H columns, W_ih (3H, I), W_hh (3H, H).
Single-threaded on purpose: `train` runs its models side by side in forked processes (one
thread each), and numba's OpenMP pool, once started in a parent, aborts a forked child that
starts it again.

The recurrence (PyTorch's GRU):

    r = sigmoid(W_ir x + b_ir + W_hr h + b_hr),  z = sigmoid(W_iz x + b_iz + W_hz h + b_hz),
    n = tanh(W_in x + b_in + r (W_hn h + b_hn)),  h' = (1 - z) n + z h.
"""

from __future__ import annotations

import numba
import numpy as np

from ftfof.surrogate.gru_kernel import _KERNEL, _ONE, gru_cell


@numba.njit(**_KERNEL)
def gru_forward(x, w_ih_t, b_ih, w_hh_t, b_hh, h_out, gates):  # pragma: no cover - compiled
    """One layer from h0 = 0 over x (B, T, I); weights transposed (I, 3H) and (H, 3H).

    Writes the hidden states h_out (B, T, H) and, for the backward pass, gates (B, T, 4, H):
    r, z, n and W_hn h + b_hn at each step.
    """
    n_seq, steps, inputs = x.shape
    width = b_hh.shape[0]
    hid = width // 3
    for b in range(n_seq):
        h = np.zeros(hid, np.float32)
        gi = np.empty(width, np.float32)
        gh = np.empty(width, np.float32)
        for t in range(steps):
            gi[:] = b_ih
            gh[:] = b_hh
            for k in range(inputs):
                xk = x[b, t, k]
                for j in range(width):
                    gi[j] += xk * w_ih_t[k, j]
            for k in range(hid):
                hk = h[k]
                for j in range(width):
                    gh[j] += hk * w_hh_t[k, j]
            for j in range(hid):
                hn = gh[2 * hid + j]
                r, z, n, h[j] = gru_cell(
                    gi[j] + gh[j], gi[hid + j] + gh[hid + j], gi[2 * hid + j], hn, h[j]
                )
                h_out[b, t, j] = h[j]
                gates[b, t, 0, j] = r
                gates[b, t, 1, j] = z
                gates[b, t, 2, j] = n
                gates[b, t, 3, j] = hn


@numba.njit(**_KERNEL)
def gru_backward(dh_out, h_out, gates, w_ih, w_hh, d_in, d_rec, dx, want_dx):  # pragma: no cover
    """Backpropagation through time of :func:`gru_forward` for every sequence at once.

    dh_out (B, T, H) is the loss's gradient on the hidden states. Writes the gradients of the
    gates' pre-activations on the input path d_in (B, T, 3H) and on the recurrent path d_rec
    (B, T, 3H) (they differ by r in the n gate), from which the weight gradients are sums over
    rows; and, if ``want_dx``, the gradient on the layer's input dx (B, T, I).
    """
    n_seq, steps, hid = dh_out.shape
    width = 3 * hid
    inputs = w_ih.shape[1]
    for b in range(n_seq):
        dh = np.zeros(hid, np.float32)
        carry = np.empty(hid, np.float32)
        for t in range(steps - 1, -1, -1):
            for j in range(hid):
                g = dh[j] + dh_out[b, t, j]
                r = gates[b, t, 0, j]
                z = gates[b, t, 1, j]
                n = gates[b, t, 2, j]
                before = h_out[b, t - 1, j] if t > 0 else np.float32(0.0)
                da_n = g * (_ONE - z) * (_ONE - n * n)
                da_r = da_n * gates[b, t, 3, j] * r * (_ONE - r)
                da_z = g * (before - n) * z * (_ONE - z)
                d_in[b, t, j] = da_r
                d_in[b, t, hid + j] = da_z
                d_in[b, t, 2 * hid + j] = da_n
                d_rec[b, t, j] = da_r
                d_rec[b, t, hid + j] = da_z
                d_rec[b, t, 2 * hid + j] = da_n * r
                carry[j] = g * z
            for i in range(width):
                gi = d_rec[b, t, i]
                for k in range(hid):
                    carry[k] += gi * w_hh[i, k]
            dh[:] = carry
            if want_dx:
                for k in range(inputs):
                    dx[b, t, k] = np.float32(0.0)
                for i in range(width):
                    gi = d_in[b, t, i]
                    for k in range(inputs):
                        dx[b, t, k] += gi * w_ih[i, k]


@numba.njit(**_KERNEL)
def linear_forward(x, w, bias, y):  # pragma: no cover - compiled
    """y (R, K) = x (R, J) w (K, J)^T + bias (K,)."""
    rows, width = x.shape
    for r in range(rows):
        for o in range(w.shape[0]):
            acc = bias[o]
            for j in range(width):
                acc += x[r, j] * w[o, j]
            y[r, o] = acc


@numba.njit(**_KERNEL)
def linear_input_grad(dy, w, dx):  # pragma: no cover - compiled
    """dx (R, J) = dy (R, K) w (K, J)."""
    rows, width = dx.shape
    for r in range(rows):
        for j in range(width):
            dx[r, j] = np.float32(0.0)
        for o in range(w.shape[0]):
            g = dy[r, o]
            for j in range(width):
                dx[r, j] += g * w[o, j]


@numba.njit(**_KERNEL)
def row_outer_sum(a, c, out, total):  # pragma: no cover - compiled
    """out (J, K) = sum_r a[r, j] c[r, k] and total (J,) = sum_r a[r, j], each over r in order."""
    rows, cols = a.shape
    width = c.shape[1]
    for j in range(cols):
        acc = np.zeros(width, np.float32)
        s = np.float32(0.0)
        for r in range(rows):
            g = a[r, j]
            s += g
            for k in range(width):
                acc[k] += g * c[r, k]
        out[j, :] = acc
        total[j] = s
