"""DILATE loss (Le Guen & Thome, NeurIPS 2019), written from the maths (FTFOF §IV.B).

For a batch of predictions p and targets y (B, N, d), with D_b[i, j] = |y_i - p_j|^2:

- soft-DTW: R[i, j] = D[i, j] + softmin_gamma(R[i-1, j-1], R[i-1, j], R[i, j-1]),
  softmin_gamma(a) = -gamma log sum exp(-a / gamma), R[0, 0] = 0, other borders +inf;
  L_shape = mean_b R_b[N, N] (not divided by N);
- the soft alignment A* = dR[N, N] / dD (a backward sweep over the stored softmin weights);
- L_temporal = mean_b <A*_b, Omega> / N^2, Omega[i, j] = (i - j)^2;
- L = alpha L_shape + (1 - alpha) L_temporal.

Gradients are exact for the batch *mean* (the reference code returns B times it). The temporal
term is differentiated through the alignment: d<A*, Omega>/dD = H Omega (H the soft-DTW Hessian)
is computed as the gradient of the directional derivative R'[N, N] along Omega, i.e. a forward
sweep for R' and a backward sweep that carries both the alignment and the derivative of the
softmin weights. Everything is float64 and compiled, vectorised over the batch along
anti-diagonals (no Python loop over series or cells).

Setting alpha and gamma from the data scale. The loss is not scale-free: D grows with the square
of the series and L_shape with N, while L_temporal does not. Our force series are divided by
their RMS (so a peak is about 3-5) on N = 100 bins; on the paper-scale validation forces (pull,
Fd, Fp as one 3-vector series) a one-bin lag raises L_shape by 0.08 and L_temporal by 0.013, a
10 % amplitude error raises L_shape by 3.0, and the exact prediction scores L_shape = -gamma
log(#near-equal paths) = -13.5 at gamma = 0.1, -1.2 at 0.01, -0.1 at 0.001. gamma must sit below
the cost of the smallest misalignment that matters, or the softmin averages over misaligned
paths and the gradient blurs peaks: 0.01 (0.1 was 4x the cost of a 10 % amplitude error).
alpha = 0.5 makes the temporal term a tie-breaker (a one-bin lag costs about what a 2 %
amplitude error does), which suits objectives that read peaks and means rather than times;
alpha = 0.25 trained worse on every force target. Flat stretches where prediction and target
are both near zero (the swing) tie every path through them, so L_temporal keeps a floor of about
0.1 even for an exact prediction: a reason not to weight it more.
"""

from __future__ import annotations

import numba
import numpy as np
import torch
from numpy.typing import NDArray

from ftfof.surrogate.fastmath import EXP_MAX, KERNEL, exp_neg, log_1_3

Array = NDArray[np.float64]


# Layout: anti-diagonal coordinates. Cell (i, j) of the (n + 2) x (m + 2) grid (1-based, with a
# border) lives at [k = i + j, i, b]; each diagonal's cells and batch form one contiguous run, and
# a cell's three predecessors (i-1, j-1), (i-1, j), (i, j-1) are the runs of diagonals k-2, k-1
# shifted by one row, so every sweep is one vectorisable loop per diagonal. Two spare diagonals
# past the last keep the backward sweeps free of boundary branches.


@numba.njit(**KERNEL)
def _sweeps(pt, yt, gamma, want_grad, values, grad_s, grad_t, E):  # pragma: no cover - compiled
    """pt (m, d, B) predictions, yt (n, d, B) targets; fills values (2, B) = (soft-DTW,
    <A*, Omega>), E (n + m + 3, n + 2, B) = the alignment, and if ``want_grad`` the gradients
    (m, d, B) of the soft-DTW and of <A*, Omega> w.r.t. the predictions."""
    m = pt.shape[0]
    n = yt.shape[0]
    W = _soft_dtw(pt, yt, gamma, values)
    _alignment(W, n, m, E)
    _omega_inner(E, n, m, values)
    if not want_grad:
        return
    Rd = _directional(W, n, m)
    G = _hessian_omega(W, E, Rd, n, m, 1.0 / gamma)
    _prediction_gradients(pt, yt, E, G, grad_s, grad_t)


@numba.njit(**KERNEL)
def _squared_distances(pt, yt, k, i0, i1, Dk):  # pragma: no cover - compiled
    """D[i, k - i] for the cells i0..i1 of diagonal ``k``, cell-major then batch, into Dk."""
    d, B = pt.shape[1], pt.shape[2]
    for ii in range(i1 - i0 + 1):
        i = i0 + ii
        j = k - i
        for b in range(B):
            acc = 0.0
            for c in range(d):
                diff = yt[i - 1, c, b] - pt[j - 1, c, b]
                acc += diff * diff
            Dk[ii * B + b] = acc


@numba.njit(**KERNEL)
def _soft_dtw(pt, yt, gamma, values):  # pragma: no cover - compiled
    """The forward sweep: values[0] = R[n, m] per series; returns the softmin weights W (3, K,
    rows, B) of each cell's three predecessors, which every later sweep reads."""
    m, _, B = pt.shape
    n = yt.shape[0]
    K = n + m + 3
    rows = n + 2
    ig = 1.0 / gamma
    W = np.zeros((3, K, rows, B))
    R = np.full((3, rows, B), np.inf)  # rolling: diagonal k lives at k % 3
    R[0, 0, :] = 0.0
    Dk = np.empty(rows * B)
    for k in range(2, n + m + 1):
        i0 = max(1, k - m)
        i1 = min(n, k - 1)
        L = (i1 - i0 + 1) * B
        _squared_distances(pt, yt, k, i0, i1, Dk)
        cur = R[k % 3]
        cur[:, :] = np.inf
        r2 = R[(k - 2) % 3].reshape(-1)[(i0 - 1) * B :]
        r1 = R[(k - 1) % 3].reshape(-1)[(i0 - 1) * B :]
        out = cur.reshape(-1)[i0 * B :]
        w0 = W[0, k].reshape(-1)[i0 * B :]
        w1 = W[1, k].reshape(-1)[i0 * B :]
        w2 = W[2, k].reshape(-1)[i0 * B :]
        for q in range(L):
            a = r2[q]
            bb = r1[q]
            c = r1[q + B]
            lo = min(a, min(bb, c))
            ea = exp_neg(min((a - lo) * ig, EXP_MAX))
            eb = exp_neg(min((bb - lo) * ig, EXP_MAX))
            ec = exp_neg(min((c - lo) * ig, EXP_MAX))
            s = ea + eb + ec
            out[q] = Dk[q] + lo - gamma * log_1_3(s)
            inv = 1.0 / s
            w0[q] = ea * inv
            w1[q] = eb * inv
            w2[q] = ec * inv
    last = R[(n + m) % 3]
    for b in range(B):
        values[0, b] = last[n, b]
    return W


@numba.njit(**KERNEL)
def _alignment(W, n, m, E):  # pragma: no cover - compiled
    """E = dR[n, m]/dD: E[k, i] = sum over successors of E[s] * (weight of (i, j) in s)."""
    B = E.shape[2]
    E[:, :, :] = 0.0
    E[n + m, n, :] = 1.0
    for k in range(n + m - 1, 1, -1):
        i0 = max(1, k - m)
        i1 = min(n, k - 1)
        L = (i1 - i0 + 1) * B
        e0 = E[k].reshape(-1)[i0 * B :]
        e1 = E[k + 1].reshape(-1)[i0 * B :]
        e2 = E[k + 2].reshape(-1)[i0 * B :]
        v0 = W[0, k + 2].reshape(-1)[i0 * B :]
        v1 = W[1, k + 1].reshape(-1)[i0 * B :]
        v2 = W[2, k + 1].reshape(-1)[i0 * B :]
        for q in range(L):
            e0[q] = e2[q + B] * v0[q + B] + e1[q + B] * v1[q + B] + e1[q] * v2[q]


@numba.njit(**KERNEL)
def _omega_inner(E, n, m, values):  # pragma: no cover - compiled
    """values[1] = <A*, Omega> per series."""
    B = E.shape[2]
    for b in range(B):
        values[1, b] = 0.0
    for k in range(2, n + m + 1):
        for i in range(max(1, k - m), min(n, k - 1) + 1):
            z = float((2 * i - k) ** 2)  # Omega = (i - j)^2
            for b in range(B):
                values[1, b] += z * E[k, i, b]


@numba.njit(**KERNEL)
def _directional(W, n, m):  # pragma: no cover - compiled
    """R' = the directional derivative of R along Omega (the same softmin weights)."""
    _, K, rows, B = W.shape
    Rd = np.zeros((K, rows, B))
    for k in range(2, n + m + 1):
        for i in range(max(1, k - m), min(n, k - 1) + 1):
            z = float((2 * i - k) ** 2)
            for b in range(B):
                Rd[k, i, b] = (
                    z
                    + W[0, k, i, b] * Rd[k - 2, i - 1, b]
                    + W[1, k, i, b] * Rd[k - 1, i - 1, b]
                    + W[2, k, i, b] * Rd[k - 1, i, b]
                )
    return Rd


@numba.njit(**KERNEL)
def _hessian_omega(W, E, Rd, n, m, ig):  # pragma: no cover - compiled
    """G = H Omega, the gradient of R'[n, m] w.r.t. D. For a successor s of cell c with weight
    w: dR'[s]/dR[c] = -w (R'[c] - (R'[s] - Omega[s])) / gamma."""
    _, K, rows, B = W.shape
    G = np.zeros((K, rows, B))
    for k in range(n + m - 1, 1, -1):
        for i in range(max(1, k - m), min(n, k - 1) + 1):
            z0 = float((2 * i - k) ** 2)  # Omega at (i+1, j+1)
            z1 = float((2 * i - k + 1) ** 2)  # at (i+1, j)
            z2 = float((2 * i - k - 1) ** 2)  # at (i, j+1)
            for b in range(B):
                rd = Rd[k, i, b]
                G[k, i, b] = (
                    W[0, k + 2, i + 1, b]
                    * (
                        G[k + 2, i + 1, b]
                        - E[k + 2, i + 1, b] * (rd - Rd[k + 2, i + 1, b] + z0) * ig
                    )
                    + W[1, k + 1, i + 1, b]
                    * (
                        G[k + 1, i + 1, b]
                        - E[k + 1, i + 1, b] * (rd - Rd[k + 1, i + 1, b] + z1) * ig
                    )
                    + W[2, k + 1, i, b]
                    * (G[k + 1, i, b] - E[k + 1, i, b] * (rd - Rd[k + 1, i, b] + z2) * ig)
                )
    return G


@numba.njit(**KERNEL)
def _prediction_gradients(pt, yt, E, G, grad_s, grad_t):  # pragma: no cover - compiled
    """Chain rule to the predictions: dD[i, j]/dpred[j] = 2 (pred[j] - target[i])."""
    m, d, B = pt.shape
    n = yt.shape[0]
    grad_s[:, :, :] = 0.0
    grad_t[:, :, :] = 0.0
    for k in range(2, n + m + 1):
        for i in range(max(1, k - m), min(n, k - 1) + 1):
            j = k - i
            for c in range(d):
                for b in range(B):
                    f = 2.0 * (pt[j - 1, c, b] - yt[i - 1, c, b])
                    grad_s[j - 1, c, b] += E[k, i, b] * f
                    grad_t[j - 1, c, b] += G[k, i, b] * f


def _compute(
    pred: Array, target: Array, gamma: float, want_grad: bool, want_alignment: bool = False
):
    """Values (B, 2), alignments (B, n, m) if asked, and gradients (B, m, d) of both terms."""
    B, m, d = pred.shape
    n = target.shape[1]
    pt = np.ascontiguousarray(np.transpose(pred, (1, 2, 0)))
    yt = np.ascontiguousarray(np.transpose(target, (1, 2, 0)))
    values = np.empty((2, B))
    grad_s = np.empty((m, d, B))
    grad_t = np.empty((m, d, B))
    E = np.empty((n + m + 3, n + 2, B))
    _sweeps(pt, yt, float(gamma), want_grad, values, grad_s, grad_t, E)
    alignment = None
    if want_alignment:
        i, j = np.meshgrid(np.arange(1, n + 1), np.arange(1, m + 1), indexing="ij")
        alignment = np.transpose(E[i + j, i], (2, 0, 1))
    return values.T, alignment, np.transpose(grad_s, (2, 0, 1)), np.transpose(grad_t, (2, 0, 1))


class _Dilate(torch.autograd.Function):
    @staticmethod
    def forward(ctx, pred, target, alpha, gamma):
        p = np.ascontiguousarray(pred.detach().cpu().numpy(), dtype=np.float64)
        y = np.ascontiguousarray(target.detach().cpu().numpy(), dtype=np.float64)
        n = y.shape[1]
        want = ctx.needs_input_grad[0]
        values, _, gs, gt = _compute(p, y, gamma, want)
        B = p.shape[0]
        shape = values[:, 0].mean()
        temporal = values[:, 1].mean() / n**2
        if want:
            ctx.save_for_backward(
                torch.from_numpy(gs / B).to(pred.dtype),
                torch.from_numpy(gt / (B * n**2)).to(pred.dtype),
            )
        ctx.alpha = alpha
        out = [alpha * shape + (1 - alpha) * temporal, shape, temporal]
        return tuple(torch.tensor(v, dtype=pred.dtype, device=pred.device) for v in out)

    @staticmethod
    def backward(ctx, g_loss, g_shape, g_temporal):
        gs, gt = ctx.saved_tensors
        a = ctx.alpha
        grad = (g_loss * a + g_shape) * gs.to(g_loss.device) + (
            g_loss * (1 - a) + g_temporal
        ) * gt.to(g_loss.device)
        return grad, None, None, None


def dilate_loss(
    pred: torch.Tensor, target: torch.Tensor, alpha: float = 0.5, gamma: float = 0.01
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """(loss, loss_shape, loss_temporal) for (B, N, d) tensors; differentiable w.r.t. ``pred``."""
    if pred.shape != target.shape or pred.dim() != 3:
        shapes = f"{tuple(pred.shape)} and {tuple(target.shape)}"
        raise ValueError(f"pred and target must both be (B, N, d); got {shapes}")
    return _Dilate.apply(pred, target, float(alpha), float(gamma))


def soft_alignment(pred: torch.Tensor, target: torch.Tensor, gamma: float = 0.01) -> np.ndarray:
    """The batch-mean soft-DTW alignment A* (N, N), for inspection and tests."""
    p = np.ascontiguousarray(pred.detach().cpu().numpy(), dtype=np.float64)
    y = np.ascontiguousarray(target.detach().cpu().numpy(), dtype=np.float64)
    _, alignment, _, _ = _compute(p, y, gamma, False, want_alignment=True)
    return alignment.mean(axis=0)


def soft_dtw(pred: np.ndarray, target: np.ndarray, gamma: float) -> np.ndarray:
    """Soft-DTW value of each series pair (B,), used for validation metrics."""
    values, _, _, _ = _compute(
        np.ascontiguousarray(pred, dtype=np.float64),
        np.ascontiguousarray(target, dtype=np.float64),
        gamma,
        False,
    )
    return values[:, 0]
