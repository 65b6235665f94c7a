"""torch modules for the surrogate whose arithmetic runs in :mod:`ftfof.surrogate.grad_kernel`.

Drop-in for ``nn.GRU(batch_first=True)`` and ``nn.Linear`` on the CPU, with the same parameter
names and shapes (a state dict loads into either), but bit-identical on any x86-64 CPU: see the
kernels' docstring for why torch's own are not. float32 only, h0 = 0, unidirectional.
"""

from __future__ import annotations

import math

import numpy as np
import torch
from torch import nn

from ftfof.surrogate import grad_kernel as kernel


def _np(t: torch.Tensor) -> np.ndarray:
    return t.detach().contiguous().numpy()


def _rows(a: np.ndarray) -> np.ndarray:
    return a.reshape(-1, a.shape[-1])


def _weight_grads(d: np.ndarray, inputs: np.ndarray) -> tuple[torch.Tensor, torch.Tensor]:
    """(sum_r d_r inputs_r^T, sum_r d_r) over every (batch, step) row."""
    d, inputs = _rows(d), _rows(inputs)
    w = np.empty((d.shape[1], inputs.shape[1]), np.float32)
    b = np.empty(d.shape[1], np.float32)
    kernel.row_outer_sum(d, inputs, w, b)
    return torch.from_numpy(w), torch.from_numpy(b)


class _GRULayerFn(torch.autograd.Function):
    @staticmethod
    def forward(ctx, x, w_ih, w_hh, b_ih, b_hh):  # type: ignore[override]
        xs = _np(x)
        n_seq, steps, _ = xs.shape
        hid = w_hh.shape[1]
        h = np.empty((n_seq, steps, hid), np.float32)
        gates = np.empty((n_seq, steps, 4, hid), np.float32)
        w_ih_n, w_hh_n = _np(w_ih), _np(w_hh)
        kernel.gru_forward(
            xs, np.ascontiguousarray(w_ih_n.T), _np(b_ih), np.ascontiguousarray(w_hh_n.T),
            _np(b_hh), h, gates,
        )  # fmt: skip
        ctx.saved = (xs, h, gates, w_ih_n, w_hh_n)
        return torch.from_numpy(h.copy())  # the caller's tensor: never the saved states

    @staticmethod
    def backward(ctx, dh):  # type: ignore[override]
        xs, h, gates, w_ih, w_hh = ctx.saved
        width = w_hh.shape[0]
        d_in = np.empty((*h.shape[:2], width), np.float32)
        d_rec = np.empty_like(d_in)
        want_dx = bool(ctx.needs_input_grad[0])
        dx = np.empty(xs.shape if want_dx else (1, 1, 1), np.float32)
        kernel.gru_backward(_np(dh), h, gates, w_ih, w_hh, d_in, d_rec, dx, want_dx)
        before = np.zeros_like(h)
        before[:, 1:] = h[:, :-1]
        dw_ih, db_ih = _weight_grads(d_in, xs)
        dw_hh, db_hh = _weight_grads(d_rec, before)
        return (torch.from_numpy(dx) if want_dx else None), dw_ih, dw_hh, db_ih, db_hh


class _LinearFn(torch.autograd.Function):
    @staticmethod
    def forward(ctx, x, w, bias):  # type: ignore[override]
        xs = _np(x)
        ws = _np(w)
        y = np.empty((*xs.shape[:-1], ws.shape[0]), np.float32)
        kernel.linear_forward(_rows(xs), ws, _np(bias), _rows(y))
        ctx.saved = (xs, ws)
        return torch.from_numpy(y)

    @staticmethod
    def backward(ctx, dy):  # type: ignore[override]
        xs, ws = ctx.saved
        dys = _np(dy)
        dx = None
        if ctx.needs_input_grad[0]:
            grad = np.empty_like(xs)
            kernel.linear_input_grad(_rows(dys), ws, _rows(grad))
            dx = torch.from_numpy(grad)
        dw, db = _weight_grads(dys, xs)
        return dx, dw, db


def _uniform(shape: tuple[int, ...], bound: float) -> nn.Parameter:
    return nn.Parameter(torch.empty(shape).uniform_(-bound, bound))


class GRU(nn.Module):
    """``nn.GRU(inputs, hidden, layers, batch_first=True, dropout)``, initialised as torch does
    (every weight and bias uniform in ±1/sqrt(hidden), drawn in the same order)."""

    def __init__(self, inputs: int, hidden: int, num_layers: int = 1, dropout: float = 0.0):
        super().__init__()
        self.num_layers, self.dropout = num_layers, dropout
        bound = 1.0 / math.sqrt(hidden)
        for layer in range(num_layers):
            width = inputs if layer == 0 else hidden
            self.register_parameter(f"weight_ih_l{layer}", _uniform((3 * hidden, width), bound))
            self.register_parameter(f"weight_hh_l{layer}", _uniform((3 * hidden, hidden), bound))
            self.register_parameter(f"bias_ih_l{layer}", _uniform((3 * hidden,), bound))
            self.register_parameter(f"bias_hh_l{layer}", _uniform((3 * hidden,), bound))

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(B, T, inputs) float32 -> hidden states (B, T, H) and the last ones (layers, B, H)."""
        last = []
        for layer in range(self.num_layers):
            if layer > 0 and self.dropout > 0:
                x = nn.functional.dropout(x, self.dropout, self.training)
            names = ("weight_ih", "weight_hh", "bias_ih", "bias_hh")
            x = _GRULayerFn.apply(x, *(getattr(self, f"{n}_l{layer}") for n in names))
            last.append(x[:, -1])
        return x, torch.stack(last)


class Linear(nn.Module):
    """``nn.Linear(inputs, outputs)`` over the last axis, initialised as torch does."""

    def __init__(self, inputs: int, outputs: int):
        super().__init__()
        bound = 1.0 / math.sqrt(inputs)
        # torch's kaiming_uniform_(a=sqrt(5)) on the weight is uniform in ±1/sqrt(fan_in)
        self.weight = _uniform((outputs, inputs), bound)
        self.bias = _uniform((outputs,), bound)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return _LinearFn.apply(x, self.weight, self.bias)
