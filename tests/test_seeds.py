"""Named random streams: deterministic, distinct, and the children of one SeedSequence."""

import numpy as np

from ftfof.seeds import STREAMS, seed_for


def test_a_stream_is_deterministic_and_streams_differ():
    assert seed_for(2025, "train", 1) == seed_for(2025, "train", 1)
    seeds = [seed_for(2025, s) for s in STREAMS] + [seed_for(2025, "train", i) for i in range(4)]
    assert len(set(seeds)) == len(seeds)
    assert seed_for(2026, "sample") not in seeds  # no offset makes one run's stream another's


def test_streams_are_the_spawned_children_of_the_base_seed():
    children = np.random.SeedSequence(7).spawn(len(STREAMS))
    split = children[STREAMS.index("split")]
    assert seed_for(7, "split") == int(split.generate_state(1)[0])
