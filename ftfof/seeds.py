"""Every random stream of the pipeline, derived from ``base.seed`` in one place.

Each stage asks for its stream by name; the streams are children of one
:class:`numpy.random.SeedSequence`, so they are independent of each other, unlike seeds made by
adding offsets to the base seed (where ``seed + 1`` of one run is ``seed`` of another).
"""

from __future__ import annotations

from typing import Literal, get_args

import numpy as np

# The position of a name is its spawn key: append new streams, never reorder, or every stream's
# numbers change.
Stream = Literal[
    "sample",  # the trajectories the sample stage draws
    "limits",  # the search for a robot's position and velocity limits
    "baselines",  # the random feasible Bezier among the common trajectories
    "acquisition",  # per-sample sensor noise on the platform
    "split",  # the train / validation split
    "train",  # initialisation and shuffling, one child per target
    "optimize",  # NSGA-II and its seeded start
    "plots",  # which samples the figures show
    "bench",  # draws of the benchmarks under bench/
    "refine",  # the feasible draws that fill a refinement round's warm-started population
    "verify",  # the perturbed copies of a simulator-checked candidate, one child per row
    "polish",  # NSGA-II on the simulator and the copies that fill its first population
    "climb",  # the climbing robot's IMU noise
    "repeat",  # evaluate's repeatability runs of the front members, one child per row
]
STREAMS: tuple[Stream, ...] = get_args(Stream)


def seed_for(base: int, stream: Stream, *index: int) -> int:
    """The seed of ``stream`` (and of its ``index``-th child) under ``base``: a 32-bit integer,
    accepted by numpy, scipy, torch and pymoo alike."""
    sequence = np.random.SeedSequence(base, spawn_key=(STREAMS.index(stream), *index))
    return int(sequence.generate_state(1)[0])
