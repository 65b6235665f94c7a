"""A search posed from the run's settings: NSGA-II's settings and the first population (a uniform
start, feasible draws, or a previous front filled up with draws)."""

from __future__ import annotations

import numpy as np

from ftfof.config import Optimize, Sample
from ftfof.optimize.search import SearchSettings, warm_population
from ftfof.seeds import seed_for
from ftfof.trajectory.policy import ConstraintPolicy


def search_settings(
    cfg: Optimize, search_seed: int, generations: int | None = None
) -> SearchSettings:
    """NSGA-II's settings; ``generations`` overrides ``cfg.generations`` (refine's rounds)."""
    return SearchSettings(
        population=cfg.population,
        generations=generations or cfg.generations,
        seed=seed_for(search_seed, "optimize"),
        crossover_eta=cfg.crossover_eta,
        crossover_prob=cfg.crossover_prob,
        mutation_eta=cfg.mutation_eta,
        log_every=cfg.log_every,
    )


def initial_population(
    policy: ConstraintPolicy,
    cfg: Optimize,
    sample: Sample,
    search_seed: int,
    warm_start_front: np.ndarray | None = None,
) -> np.ndarray | None:
    """Free-variable rows to start from, or None for pymoo's uniform start. ``warm_start_front``
    (full decision rows of a previous front) seeds it, filled up with feasible draws; otherwise
    ``cfg.seeded_start`` starts from feasible draws."""
    from ftfof.trajectory.sampling import sample_feasible

    s = sample
    if warm_start_front is not None:
        front = policy.contract(warm_start_front)
        need = max(cfg.population - len(front), 0)
        fill = np.empty((0, policy.n_free))
        if need:
            fill_seed = seed_for(search_seed, "refine")
            drawn = sample_feasible(policy, need, fill_seed, s.design, s.batch, s.max_draws)
            fill = policy.contract(drawn.X)
        return warm_population(front, fill, cfg.population)
    if cfg.seeded_start:
        seed = seed_for(search_seed, "optimize")
        drawn = sample_feasible(policy, cfg.population, seed, s.design, s.batch, s.max_draws)
        return policy.contract(drawn.X)
    return None
