"""Which bond connectors may be switched off: those of broken bonds well clear of the plate
(docs/simulator.md, "Adhesive interface"; :class:`ftfof.sim.padstate.PadTracker` switches them).
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

# a broken node this far above the plate (m), and not closing faster than it can cover in
# IDLE_STEPS steps, has its connector switched off (:func:`idle_changes`)
IDLE_HEIGHT, IDLE_STEPS = 1.0e-3, 4.0


@numba.njit(cache=True)
def idle_changes(
    q: Array,
    qd: Array,
    node_index: NDArray[np.int64],
    plate_index: int,
    broken: NDArray[np.bool_],
    idle: NDArray[np.bool_],
    h: float,
    changed: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """Mark idle the broken nodes well clear of the plate, wake those that come near; lists the
    nodes that changed in ``changed`` and returns how many.

    A broken node's connector pulls nothing while the node is above the plate (no bond, no
    contact: its force is exactly zero), yet the solver evaluates its user function on every
    Newton iteration; about half a run's cost is the bond connectors. Switching off the idle ones
    leaves every residual bit for bit as it was, as long as no idle node reaches the plate within
    a step: hence the height margin and the look-ahead at the node's approach speed.
    """
    n_changed = 0
    zp, vzp = q[plate_index + 1], qd[plate_index + 1]
    for i in range(node_index.size):
        j = node_index[i]
        closing = max(vzp - qd[j + 1], 0.0)
        clear = q[j + 1] - zp - IDLE_STEPS * closing * h > IDLE_HEIGHT
        now = broken[i] and clear
        if now != idle[i]:
            idle[i] = now
            changed[n_changed] = i
            n_changed += 1
    return n_changed
