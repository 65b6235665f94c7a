"""The trained surrogate as one fast, batched trajectory -> target series map for the optimiser.

PyTorch's CPU GRU pays a dispatch per time step (about 18 ms for 200 sequences of 100 steps) and a
NumPy step loop pays one per operation (about 100 ms); here each layer's input projections are one
GEMM and the recurrence is one compiled float32 kernel over the whole population
(:mod:`ftfof.surrogate.gru_kernel`), with PyTorch's equations (gates r, z, n in that order):

    r = s(W_ir x + b_ir + W_hr h + b_hr),  z = s(W_iz x + b_iz + W_hz h + b_hz)
    n = tanh(W_in x + b_in + r * (W_hn h + b_hn)),  h' = (1 - z) * n + z * h

float32 is the precision the models were trained in; series come back as float64, by name.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ftfof.data.dataset import Normalization
from ftfof.data.targets import time_base
from ftfof.surrogate.gru_kernel import Layer
from ftfof.surrogate.peaks import PeakPredictor

Array = NDArray[np.float64]


@dataclass(frozen=True)
class GRUWeights:
    """One ForceGRU's weights: its GRU layers and the linear K-output head, float32."""

    layers: tuple[Layer, ...]
    head_w: NDArray[np.float32]  # (K, hidden)
    head_b: NDArray[np.float32]  # (K,)

    @classmethod
    def from_state(cls, state: dict[str, NDArray]) -> GRUWeights:
        n = sum(1 for k in state if k.startswith("gru.weight_ih_l"))
        layers = tuple(
            Layer.from_torch(
                *(state[f"gru.{p}_l{i}"] for p in ("weight_ih", "weight_hh", "bias_ih", "bias_hh"))
            )
            for i in range(n)
        )
        head_w = np.asarray(state["head.weight"], np.float32)
        head_b = np.asarray(state["head.bias"], np.float32).reshape(-1)
        return cls(layers, np.ascontiguousarray(head_w), np.ascontiguousarray(head_b))

    @property
    def outputs(self) -> int:
        return len(self.head_b)

    def __call__(self, x: NDArray) -> Array:
        """(pop, N, inputs) normalised -> (pop, N, K) normalised targets (softplus >= 0)."""
        seq = np.ascontiguousarray(x, dtype=np.float32)
        for layer in self.layers[:-1]:
            seq = layer.hidden_states(seq)
        y = self.layers[-1].head(seq, self.head_w, self.head_b).astype(np.float64)
        return np.logaddexp(0.0, y)  # softplus


@dataclass(frozen=True)
class Surrogate:
    """Trajectory samples on the dataset's time base -> the named target series, in their units.

    ``targets`` names the model's outputs in order; ``trained`` those the training data supplied
    (a target no training sample had, e.g. the film channel of an older acquisition, is untrained
    and must not be read as a prediction). ``peaks``: target -> the GP of its peak on the control
    values (:mod:`ftfof.surrogate.peaks`); such a target's series keeps the GRU's shape, scaled
    so that its maximum is the GP's.
    """

    model: GRUWeights
    targets: tuple[str, ...]
    trained: tuple[str, ...]
    normalization: Normalization
    seq_len: int
    hold: float
    peaks: Mapping[str, PeakPredictor] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.model.outputs != len(self.targets):
            raise ValueError(
                f"the model has {self.model.outputs} outputs for {len(self.targets)} targets"
            )

    def time_base(self, T3: float) -> Array:
        return time_base(T3, self.hold, self.seq_len)

    def features(self, position: Array, velocity: Array) -> Array:
        """(pop, N, 2) positions and velocities -> normalised (pop, N, 4) inputs."""
        raw = np.concatenate([position, velocity], axis=-1)
        return (raw - np.asarray(self.normalization.input_mean)) / np.asarray(
            self.normalization.input_scale
        )

    def predict(
        self,
        position: Array,
        velocity: Array,
        names: Sequence[str] | None = None,
        decisions: Array | None = None,
    ) -> dict[str, Array]:
        """Target name -> (pop, N) series for trajectories sampled at :meth:`time_base`; every
        trained target unless ``names`` says which. ``decisions``: the trajectories' (pop, 12)
        control values, which the peak models read (required when one is asked for)."""
        names = self.trained if names is None else tuple(names)
        untrained = [n for n in names if n not in self.trained]
        if untrained:
            raise ValueError(f"the surrogate was not trained on {untrained} (has {self.trained})")
        peaked = [n for n in names if n in self.peaks]
        if peaked and decisions is None:
            raise ValueError(f"the peaks of {peaked} come from the control values: pass decisions")
        if peaked and len(np.atleast_2d(decisions)) != len(position):
            raise ValueError(
                f"{len(np.atleast_2d(decisions))} rows of control values for "
                f"{len(position)} trajectories"
            )
        y = self.normalization.from_model(self.model(self.features(position, velocity)))
        series = {n: y[..., self.targets.index(n)] for n in names}
        for n in peaked:
            series[n] = with_peak(series[n], self.peaks[n](decisions, series[n].max(axis=-1)))
        return series


def with_peak(series: Array, peak: Array) -> Array:
    """(pop, N) ``series`` scaled so that each row's maximum is ``peak`` (pop,): the shape of one
    model, the level of another. A row that is 0 throughout has no shape: it becomes the peak."""
    top = np.max(series, axis=-1, keepdims=True)
    peak = np.asarray(peak, dtype=float)[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(top > 0, series * (peak / top), peak)
