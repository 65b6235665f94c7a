"""Trained surrogates as one fast, batched trajectory -> (Fd, Fp) map for the optimiser.

PyTorch's CPU GRU pays a dispatch per time step (about 18 ms for 200 sequences of 100 steps) and a
NumPy step loop pays one per operation (about 100 ms); here each layer's input projections are one
GEMM and the recurrence is one compiled float32 kernel over the whole population
(:mod:`ftfof.surrogate.gru_kernel`), with PyTorch's equations (gates r, z, n in that order):

    r = s(W_ir x + b_ir + W_hr h + b_hr),  z = s(W_iz x + b_iz + W_hz h + b_hz)
    n = tanh(W_in x + b_in + r * (W_hn h + b_hn)),  h' = (1 - z) * n + z * h

float32 is the precision the models were trained in; forces come back as float64.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ftfof.data.dataset import Normalization, time_base
from ftfof.surrogate.gru_kernel import Layer

Array = NDArray[np.float64]


@dataclass(frozen=True)
class GRUWeights:
    """One ForceGRU's weights: its GRU layers and the linear head, float32."""

    layers: tuple[Layer, ...]
    head_w: NDArray[np.float32]  # (hidden,)
    head_b: float

    @classmethod
    def from_state(cls, state: dict[str, NDArray]) -> GRUWeights:
        n = sum(1 for k in state if k.startswith("gru.weight_ih_l"))
        layers = tuple(
            Layer.from_torch(
                *(state[f"gru.{p}_l{i}"] for p in ("weight_ih", "weight_hh", "bias_ih", "bias_hh"))
            )
            for i in range(n)
        )
        head_w = np.ascontiguousarray(np.asarray(state["head.weight"], np.float32).reshape(-1))
        return cls(layers, head_w, float(np.asarray(state["head.bias"]).reshape(-1)[0]))

    def __call__(self, x: NDArray) -> Array:
        """(pop, N, inputs) normalised -> (pop, N) normalised force (softplus >= 0)."""
        seq = np.ascontiguousarray(x, dtype=np.float32)
        for layer in self.layers[:-1]:
            seq = layer.hidden_states(seq)
        y = self.layers[-1].head(seq, self.head_w, self.head_b).astype(np.float64)
        return np.logaddexp(0.0, y)  # softplus


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
