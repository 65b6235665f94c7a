"""The watchdog alone: it stops a run on a non-finite state or past its time budget, and calls
a fall when a stance pad lets go or the body leaves its plan."""

from __future__ import annotations

import numpy as np

from ftfof.climb.watchdog import CHECK_EVERY, Watchdog

START = 0.25  # s, the first lift-off
HELD = np.ones(4, dtype=bool)


def _plan(t):
    return np.full_like(t, 0.01), np.zeros_like(t)  # the body planned 10 mm up the wall


def _dog(params, **changes):
    return Watchdog(params.climb.model_copy(update=changes), START, tree=2)


def _state(x: float, z: float = 0.0) -> np.ndarray:
    q = np.zeros(10)
    q[2:4] = x, z
    return q


def test_a_nan_state_stops_the_run_at_the_next_check(params):
    dog = _dog(params)
    q = _state(0.01)
    q[7] = np.nan
    assert all(dog.step(0.1, q) for _ in range(CHECK_EVERY - 1))
    assert not dog.step(0.1, q)
    assert dog.stopped == "non-finite state at t = 0.1000 s" and dog.steps == CHECK_EVERY


def test_a_spent_time_budget_stops_the_run(params):
    dog = _dog(params, time_budget=0.0)
    assert not all(dog.step(0.2, _state(0.01)) for _ in range(CHECK_EVERY))
    assert dog.stopped.startswith("time budget of 0.0 s exceeded at t = 0.2000 s")
    assert _dog(params).step(0.2, _state(0.01))  # within the budget, a finite state runs on


def test_a_body_off_its_plan_is_a_fall(params):
    dog = _dog(params)
    near = params.climb.fall_distance * 0.9
    assert not dog.fell(1.0, _state(0.01 + near), HELD, -1, _plan)
    assert not dog.fell(1.0, _state(0.01, near), HELD, -1, _plan)
    assert dog.fall is None
    assert dog.fell(1.0, _state(0.01 - 1.2 * params.climb.fall_distance), HELD, -1, _plan)
    assert dog.fall.time == 1.0 and "left its plan by 24.0 mm" in dog.fall.why


def test_a_stance_pad_letting_go_is_a_fall_but_not_the_swinging_one(params):
    fr_off = np.array([True, False, True, True])
    assert not _dog(params).fell(1.0, _state(0.01), fr_off, 1, _plan)  # FR swings
    assert not _dog(params).fell(START, _state(0.01), fr_off, -1, _plan)  # not before lift-off
    dog = _dog(params)
    assert dog.fell(1.0, _state(0.01), fr_off, 0, _plan)
    assert dog.fall.why == "the FR stance pad let go at t = 1.000 s"
