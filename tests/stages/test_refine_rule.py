"""The refinement's stop rule: fidelity on the first priority *and* a front the simulator passes."""

import numpy as np

from ftfof.config import RefineTarget
from ftfof.evaluate.fidelity import fidelity
from ftfof.pipeline.refine import round_target_met

S = np.array([[1.0], [2.0], [3.0], [4.0], [5.0]])
RANKED = fidelity(["fs1"], S * 1.01, S)[0]  # rho 1, 1 % off
TARGET = RefineTarget(spearman=0.9, relative_error=0.15, clean=0.9)


def test_fidelity_and_a_clean_front_stop_the_refinement():
    assert round_target_met(TARGET, RANKED, 0.01, clean=0.95)


def test_a_front_of_exploits_refines_on_even_when_fs1_ranks_well():
    assert not round_target_met(TARGET, RANKED, 0.01, clean=0.5)


def test_a_clean_front_ranked_badly_refines_on():
    reversed_ranks = fidelity(["fs1"], S[::-1], S)[0]
    assert not round_target_met(TARGET, reversed_ranks, 0.01, clean=1.0)
    assert not round_target_met(TARGET, RANKED, 0.5, clean=1.0)  # the optimum itself far off
