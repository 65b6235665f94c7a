"""Trained surrogates as one fast, batched trajectory -> (Fd, Fp) map for the optimiser.

PyTorch's CPU GRU pays a dispatch per time step (about 18 ms for 200 sequences of 100 steps);
here the GRU runs in NumPy: all input projections in one GEMM, then one small GEMM per step for
the whole population. The equations are PyTorch's (gates r, z, n in that order):

    r = s(W_ir x + b_ir + W_hr h + b_hr),  z = s(W_iz x + b_iz + W_hz h + b_hz)
    n = tanh(W_in x + b_in + r * (W_hn h + b_hn)),  h' = (1 - z) * n + z * h
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.data.dataset import Normalization, time_base

Array = NDArray[np.float64]


@dataclass(frozen=True)
class GRUWeights:
    """One ForceGRU's weights as float64 arrays (layers of (W_ih, W_hh, b_ih, b_hh), head)."""

    layers: tuple[tuple[Array, Array, Array, Array], ...]
    head_w: Array  # (1, hidden)
    head_b: Array  # (1,)

    @classmethod
    def from_state(cls, state: dict[str, Array]) -> GRUWeights:
        n = sum(1 for k in state if k.startswith("gru.weight_ih_l"))
        layers = tuple(
            tuple(
                np.asarray(state[f"gru.{p}_l{i}"], dtype=np.float64)
                for p in ("weight_ih", "weight_hh", "bias_ih", "bias_hh")
            )
            for i in range(n)
        )
        return cls(
            layers,
            np.asarray(state["head.weight"], np.float64),
            np.asarray(state["head.bias"], np.float64),
        )

    def __call__(self, x: Array) -> Array:
        """(pop, N, inputs) normalised -> (pop, N) normalised force (softplus >= 0)."""
        seq = np.asarray(x, dtype=np.float64)
        for w_ih, w_hh, b_ih, b_hh in self.layers:
            hidden = w_hh.shape[1]
            gi = seq @ w_ih.T + b_ih  # (pop, N, 3h): every step's input projection at once
            h = np.zeros((seq.shape[0], hidden))
            out = np.empty((seq.shape[0], seq.shape[1], hidden))
            for t in range(seq.shape[1]):
                gh = h @ w_hh.T + b_hh
                r = _sigmoid(gi[:, t, :hidden] + gh[:, :hidden])
                z = _sigmoid(gi[:, t, hidden : 2 * hidden] + gh[:, hidden : 2 * hidden])
                n = np.tanh(gi[:, t, 2 * hidden :] + r * gh[:, 2 * hidden :])
                h = (1.0 - z) * n + z * h
                out[:, t] = h
            seq = out
        y = seq @ self.head_w.T + self.head_b
        return np.logaddexp(0.0, y[..., 0])  # softplus


def _sigmoid(x: Array) -> Array:
    return 0.5 * (1.0 + np.tanh(0.5 * x))


@dataclass(frozen=True)
class Surrogate:
    """Trajectory samples on the dataset's time base -> predicted Fd and Fp in newtons."""

    detachment: GRUWeights
    pre_pressure: GRUWeights
    normalization: Normalization
    seq_len: int
    hold: float

    def time_base(self, T3: float) -> Array:
        return time_base(T3, self.hold, self.seq_len)

    def features(self, position: Array, velocity: Array) -> Array:
        """(pop, N, 2) positions and velocities -> normalised (pop, N, 4) inputs."""
        raw = np.concatenate([position, velocity], axis=-1)
        return (raw - np.asarray(self.normalization.input_mean)) / np.asarray(
            self.normalization.input_scale
        )

    def forces(self, position: Array, velocity: Array) -> tuple[Array, Array]:
        """(Fd, Fp), each (pop, N), for trajectories sampled at :meth:`time_base`."""
        x = self.features(position, velocity)
        scale = self.normalization.target_scale
        return self.detachment(x) * scale[0], self.pre_pressure(x) * scale[1]
