"""The pipeline's commands, one module per DVC stage, registered in :mod:`stages.cli`.

Importing the package pins the numerical code paths (:func:`stages.runtime.pin_numerics`)
before any stage loads torch or numba, so every entry point (`ftfof`, `python -m ftfof`, tests)
computes the same numbers on any x86-64 machine.
"""

from stages.runtime import pin_numerics

pin_numerics()
