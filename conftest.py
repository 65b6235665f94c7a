"""Loaded before tests/conftest.py: pins the numerical code paths
(:func:`stages.runtime.pin_numerics`) before any test module imports numpy, so that a test
process, the local pool it forks and the Dask workers it spawns all compute with the same numpy
kernels as the pipeline's own processes."""

import stages  # noqa: F401  (pins on import)
