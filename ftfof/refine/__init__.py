"""Refinement: what each round decides from the simulations of where the optimiser went, as pure
functions (the files, the simulations and the tracking are :mod:`ftfof.pipeline.refine`'s)."""
