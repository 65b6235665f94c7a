"""The film's element grid: uniform as it always was, or graded: short at the pad's ends."""

import numpy as np
import pytest

from ftfof.sim.film import clamp_edge, clamp_pins
from ftfof.sim.pad import film_grid

PAD, WIDTH, GRIP = 0.05, 0.02, 0.005


@pytest.mark.parametrize("elements", [10, 20, 30, 40, 80])
def test_the_uniform_grid_is_todays_to_the_last_bit(elements):
    grid = film_grid(PAD, elements, WIDTH, GRIP)
    dx = PAD / elements
    area = np.full(elements + 1, WIDTH * dx)
    area[[0, -1]] /= 2
    np.testing.assert_array_equal(grid.x_ref, np.linspace(0.0, PAD, elements + 1))
    np.testing.assert_array_equal(grid.area, area)
    assert (grid.length == dx).all()
    for x in clamp_pins(grid.x_ref, GRIP):  # the pins where the uniform film has had them
        e = min(int(x // dx + 1e-9), elements - 1)
        assert grid.element_at(x) == e and x - grid.start[e] == x - e * dx


@pytest.mark.parametrize(("elements", "edge"), [(16, 1.25e-3), (20, 1.25e-3), (30, 1e-3)])
def test_the_graded_grid_ends_the_grip_on_a_node_and_spreads_the_pad_area(elements, edge):
    grid = film_grid(PAD, elements, WIDTH, GRIP, edge)
    length = np.diff(grid.x_ref)
    assert grid.x_ref.size == elements + 1 and grid.x_ref[0] == 0.0 and grid.x_ref[-1] == PAD
    assert (length > 0).all()
    assert grid.x_ref[clamp_edge(grid.x_ref, GRIP)] == pytest.approx(GRIP, abs=1e-12)
    assert length[: clamp_edge(grid.x_ref, GRIP) + 1].max() <= edge * (1 + 1e-9)
    pad = length[clamp_edge(grid.x_ref, GRIP) :]
    assert pad[0] == pytest.approx(edge) and pad[-1] == pytest.approx(edge)
    assert pad.max() > 2 * edge and (pad <= pad.max()).all()
    middle = int(np.argmax(pad))
    assert (np.diff(pad[: middle + 1]) >= 0).all() and (np.diff(pad[middle:]) <= 0).all()
    tributary = (np.r_[0.0, length] + np.r_[length, 0.0]) / 2
    np.testing.assert_allclose(grid.area, WIDTH * tributary)
    assert grid.area.sum() == pytest.approx(PAD * WIDTH, rel=1e-12)
    for i, x in enumerate(grid.x_ref[:-1]):  # a node belongs to the element it starts
        assert grid.element_at(x) == i


def test_a_graded_grid_with_no_room_to_grow_is_refused():
    with pytest.raises(ValueError, match="cannot start"):
        film_grid(PAD, 40, WIDTH, GRIP, 1.25e-3)  # 36 elements of 1.25 mm fill the pad exactly
