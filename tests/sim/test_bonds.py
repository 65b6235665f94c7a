"""The cohesive bond law and its per-step state machine, without the simulator."""

import exudyn as exu
import numpy as np
import pytest

from ftfof.sim import bonds
from ftfof.sim.bonds import BondLaw, BondState
from ftfof.sim.idle import IDLE_HEIGHT, IDLE_STEPS, idle_changes


@pytest.fixture
def law(params):
    return BondLaw.from_surface(params.selected_surface, 1e-4)


def test_bilinear_law_releases_exactly_the_fracture_energy(law, params):
    s = params.selected_surface
    r, d_n = law.elastic_fraction, law.critical_opening
    assert 0 < r < 1
    assert law.stiffness == pytest.approx(s.contact_stiffness)  # as stiff as the foam presses
    assert law.stiffness * r * d_n == pytest.approx(s.strength)  # peak traction
    assert 0.5 * s.strength * d_n == pytest.approx(s.fracture_energy)  # the triangle's area


def test_softening_follows_the_bilinear_law_and_keeps_its_damage(law):
    """Past the peak the traction falls linearly to zero at the critical opening, and an
    unloaded bond keeps its damage (secant unloading)."""
    film = Film(1)
    state = BondState.bonded(film.x, 1e6, law)
    phi = state.scale[0]
    r, d_n = law.elastic_fraction, law.critical_opening
    for lam in (0.5 * r, *(r + f * (1 - r) for f in (0.05, 0.3, 0.6, 0.9))):  # rising
        film.q[film.node_index[0] + 1] = lam * d_n
        film.step(state, law)
        traction = state.scale[0] * law.stiffness * lam * d_n
        peak = phi * law.stiffness * r * d_n
        expected = peak * min(lam / r, (1 - lam) / (1 - r))
        assert traction == pytest.approx(expected, rel=0.03), lam
    damaged = state.scale[0]
    film.q[film.node_index[0] + 1] = 0.1 * d_n
    film.step(state, law)
    assert state.scale[0] == damaged and not state.broken[0]


def test_contact_ramp_is_c1_and_zero_when_apart(law):
    w = law.contact_smoothing
    u = np.array([1e-3, 0.0, -w / 2, -w, -2 * w])
    p = law.contact_pressure(u, np.zeros_like(u))
    assert p[0] == 0 and p[1] == 0
    assert p[3] == pytest.approx(law.contact_stiffness * w / 2)
    # slope continuous at the end of the ramp: Kc on both sides
    eps = 1e-9
    left = law.contact_pressure(np.array([-w + eps, -w - eps]), np.zeros(2))
    assert (left[1] - left[0]) / (2 * eps) == pytest.approx(law.contact_stiffness, rel=1e-3)


def test_arrays_the_kernel_and_the_connector_share_one_contact_law(law):
    """The numpy mirror, the compiled step and the connector's symbolic user function all
    evaluate :func:`bonds.contact_pressure`: the same pressures for the same opening and rate."""
    w = law.contact_smoothing
    u = np.array([1e-3, 0.0, -w / 2, -w, -3 * w, -3 * w])
    # closing (v < 0) stiffens the contact; the last node opens too fast to push at all
    v = np.array([0.0, 0.1, -0.2, 0.01, 0.03, 2 / law.hunt_crossley])
    expected = law.contact_pressure(u, v)
    assert expected[-1] == 0 and (expected[2:-1] > 0).all()
    film = Film(len(u))  # bonded at no preload: after a step p_max is the kernel's pressure
    state = BondState.bonded(film.x, 0.0, law)
    film.q[film.node_index + 1] = u
    film.qd[film.node_index + 1] = v
    film.step(state, law)
    assert state.p_max.tolist() == expected.tolist()
    esym = exu.symbolic
    symbolic = [
        bonds.contact_pressure(
            esym.Real(float(a)),
            esym.Real(float(b)),
            law.contact_stiffness,
            w,
            law.hunt_crossley,
            esym.max,
            esym.min,
        ).Evaluate()
        for a, b in zip(u, v, strict=True)
    ]
    assert symbolic == expected.tolist()


class Film:
    """A fake state vector: plate node (x, z) then film nodes (x, z, slope_x, slope_y)."""

    def __init__(self, n: int):
        self.q = np.zeros(2 + 4 * n)
        self.qd = np.zeros_like(self.q)
        self.node_index = 2 + 4 * np.arange(n, dtype=np.int64)
        self.x = np.linspace(0.0, 0.05, n)
        self.area = np.full(n, 1e-4)

    def step(self, state: BondState, law: BondLaw, h: float = 5e-4):
        push = np.zeros(len(self.x), dtype=np.int64)
        kind = np.zeros_like(push)
        out = bonds.step(
            self.q,
            self.qd,
            self.node_index,
            0,
            self.x,
            self.area,
            *state.arrays(),
            h,
            bonds.kernel_law(law),
            push,
            kind,
        )
        n = out[0]
        return out, list(zip(push[:n].tolist(), kind[:n].tolist(), strict=True))


def test_opening_past_the_critical_separation_breaks_and_reports_it(law):
    film = Film(3)
    state = BondState.bonded(film.x, 5000.0, law)
    film.q[film.node_index[1] + 1] = 1.01 * law.critical_opening
    (_, n_bonded, lowest, lam), pushes = film.step(state, law)
    assert pushes == [(1, bonds.BREAK)]
    assert state.broken.tolist() == [False, True, False]
    assert n_bonded == 2 and lowest == pytest.approx(0.0)
    assert lam == pytest.approx(0.0)  # the remaining bonds are unloaded


def test_mixed_mode_criterion_combines_opening_and_slip(law):
    film = Film(1)
    state = BondState.bonded(film.x, 5000.0, law)
    film.q[film.node_index[0]] = 0.7 * law.shear_opening  # slip
    film.q[film.node_index[0] + 1] = 0.7 * law.critical_opening  # opening: lambda = 0.99
    _, pushes = film.step(state, law)
    assert (0, bonds.BREAK) not in pushes
    film.q[film.node_index[0] + 1] = 0.75 * law.critical_opening  # lambda = 1.03
    _, pushes = film.step(state, law)
    assert pushes == [(0, bonds.BREAK)]


def test_each_mode_releases_its_own_fracture_energy(law, params):
    s = params.selected_surface
    tau, G_II = s.strength * s.shear_capacity_ratio, s.fracture_energy * s.shear_energy_ratio
    assert law.shear_strength == pytest.approx(tau)
    assert law.shear_stiffness * law.elastic_fraction * law.shear_opening == pytest.approx(tau)
    assert 0.5 * tau * law.shear_opening == pytest.approx(G_II)


def _pressed(law: BondLaw, depth: float = 2.0) -> tuple[float, float]:
    """A node pressed ``depth`` ramp widths in: its opening and its contact pressure."""
    un = -depth * law.contact_smoothing
    return un, float(law.contact_pressure(np.array([un]), np.zeros(1))[0])


def test_a_pressed_bond_breaks_on_its_own_opening_with_friction_beside_it(law):
    """The shear allowance takes no friction: a slip past d_t breaks a pressed bond as it does
    a free one, and the node's slider then holds it at mu N from where it slid."""
    film = Film(1)
    un, p = _pressed(law)
    film.q[film.node_index[0] + 1] = un
    film.q[film.node_index[0]] = 1.01 * law.shear_opening
    state = BondState.bonded(film.x, 1e6, law)
    normal = film.area[0] * (p + state.scale[0] * law.stiffness * -un)
    _, pushes = film.step(state, law)
    assert pushes == [(0, bonds.BREAK | bonds.SLIDE)]
    stretch = film.x[0] + film.q[film.node_index[0]] - state.slider[0]
    kt = law.shear_stiffness * film.area[0]
    assert kt * stretch == pytest.approx(law.friction * normal, rel=1e-9)
    assert state.slider_pushed[0] == state.slider[0]


def test_the_slider_sticks_below_mu_n_without_creep_and_slides_at_it(law):
    """Return mapping: a node moved less than mu N / k_t keeps its anchor, however often it is
    stepped; moved further, the anchor trails it by exactly that much."""
    film = Film(1)
    un, p = _pressed(law, 0.3)
    assert 0 < p < law.rebond_pressure  # pressed too lightly to re-bond
    film.q[film.node_index[0] + 1] = un
    state = BondState.bonded(film.x, 1e6, law)
    state.broken[:] = True  # friction alone
    reach = law.friction * p / law.shear_stiffness  # the slider's elastic reach, m
    film.q[film.node_index[0]] = 0.9 * reach
    for _ in range(50):
        film.step(state, law)
        assert state.slider[0] == film.x[0]
    film.q[film.node_index[0]] = 3 * reach
    film.step(state, law)
    assert state.slider[0] == pytest.approx(film.x[0] + 2 * reach, rel=1e-9)


def test_a_broken_node_rebonds_only_while_its_slider_sticks(law):
    film = Film(1)
    un, p = _pressed(law)
    assert p > law.rebond_pressure
    film.q[film.node_index[0] + 1] = un
    state = BondState.bonded(film.x, 5000.0, law)
    state.broken[:] = True
    film.q[film.node_index[0]] = 1e-3  # slid 1 mm since the last step: sliding
    _, pushes = film.step(state, law)
    assert state.broken[0] and pushes == [(0, bonds.SLIDE)]
    _, pushes = film.step(state, law)  # held where it is: it sticks, and re-bonds
    assert not state.broken[0] and pushes == [(0, bonds.REBOND)]


def test_the_rate_factor_follows_the_current_opening_rate_not_its_peak(law):
    """A bond opened fast and then held has R back at 1 (R - 1 decays as exp(-n t / filter))."""
    film = Film(1)
    state = BondState.bonded(film.x, 1e6, law)
    film.q[film.node_index[0] + 1] = 0.5 * law.elastic_fraction * law.critical_opening
    film.qd[film.node_index[0] + 1] = 0.5
    for _ in range(100):
        film.step(state, law)
    assert state.rate[0] > 1.5
    film.qd[film.node_index[0] + 1] = 0.0
    for _ in range(int(30 * bonds.RATE_FILTER / 5e-4)):
        film.step(state, law)
    assert 1.0 <= state.rate[0] < 1.001
    assert state.scale[0] == pytest.approx(float(law.preload_factor(1e6)), rel=bonds.PUSH_STEP)


def test_a_drag_rate_factor_reads_the_shear_opening_in_normal_units(law):
    v = 0.01
    opening = v * law.critical_opening / law.shear_opening
    assert law.drag_rate_factor(v) == pytest.approx(
        1 + (opening / law.rate_speed) ** law.rate_exponent
    )
    assert law.drag_rate_factor(0.0) == 1.0


def test_shear_rate_raises_the_scale_like_opening_rate(law):
    """The rate factor follows the mixed-mode opening: a fast slip stiffens the bond too."""
    film = Film(1)
    state = BondState.bonded(film.x, 1e6, law)
    before = state.scale[0]
    film.q[film.node_index[0]] = 0.5 * law.elastic_fraction * law.shear_opening  # before the peak
    film.qd[film.node_index[0]] = 0.5 * law.shear_opening / law.critical_opening  # ~0.5 m/s
    for _ in range(100):
        film.step(state, law)
    assert state.rate[0] > 1.5
    assert state.scale[0] > before * 1.5


def test_broken_node_pressed_hard_rebonds_where_it_lies(law):
    film = Film(2)
    state = BondState.bonded(film.x, 5000.0, law)
    state.broken[:] = True
    film.q[film.node_index[0]] = 0.003  # moved 3 mm along x, where its slider came to rest
    state.slider[0] = state.slider_pushed[0] = film.x[0] + 0.003
    film.q[film.node_index[0] + 1] = -3 * law.contact_smoothing  # pressed in
    _, pushes = film.step(state, law)
    assert pushes == [(0, bonds.REBOND)]
    assert not state.broken[0] and state.broken[1]
    assert state.anchor[0] == pytest.approx(film.x[0] + 0.003)
    assert state.scale[0] == pytest.approx(float(law.preload_factor(state.p_max[0])))


def test_preload_raises_the_bond_scale_and_saturates(law):
    film = Film(1)
    state = BondState.bonded(film.x, 0.0, law)
    scales = []
    for depth in (1, 2, 5, 20, 200):
        film.q[film.node_index[0] + 1] = -depth * law.contact_smoothing
        film.step(state, law)
        scales.append(state.scale[0])
    assert scales == sorted(scales)
    assert scales[-1] <= 1.0 and scales[-1] - scales[-2] < scales[1] - scales[0]


def test_opening_rate_raises_the_scale_of_a_loaded_bond(law):
    film = Film(1)
    state = BondState.bonded(film.x, 1e6, law)
    before = state.scale[0]
    film.q[film.node_index[0] + 1] = 0.5 * law.elastic_fraction * law.critical_opening
    film.qd[film.node_index[0] + 1] = 0.5  # m/s opening
    for _ in range(100):
        film.step(state, law)
    assert state.rate[0] > 1.5
    assert state.scale[0] > before * 1.5


def _idle(film: Film, broken: list[bool], idle: np.ndarray, h: float = 5e-4) -> list[int]:
    changed = np.zeros(len(film.x), dtype=np.int64)
    n = idle_changes(film.q, film.qd, film.node_index, 0, np.array(broken), idle, h, changed)
    return changed[:n].tolist()


def test_only_broken_nodes_clear_of_the_plate_go_idle():
    """Node 0 bonded and high, 1 broken and high, 2 broken and touching, 3 broken and high but
    closing fast enough to reach the plate within the look-ahead."""
    film = Film(4)
    high = 2 * IDLE_HEIGHT
    for i in (0, 1, 3):
        film.q[film.node_index[i] + 1] = high
    film.qd[film.node_index[3] + 1] = -high / (IDLE_STEPS * 5e-4)
    idle = np.zeros(4, dtype=bool)
    assert _idle(film, [False, True, True, True], idle) == [1]
    assert idle.tolist() == [False, True, False, False]
    assert _idle(film, [False, True, True, True], idle) == []  # nothing new: nothing pushed


def test_an_idle_node_wakes_when_it_comes_near_the_plate_or_the_plate_comes_up():
    film = Film(2)
    film.q[film.node_index + 1] = 2 * IDLE_HEIGHT
    idle = np.zeros(2, dtype=bool)
    assert _idle(film, [True, True], idle) == [0, 1]
    film.q[film.node_index[0] + 1] = 0.5 * IDLE_HEIGHT  # node 0 sinks
    assert _idle(film, [True, True], idle) == [0]
    film.q[1] = 1.5 * IDLE_HEIGHT  # the plate rises under node 1
    assert _idle(film, [True, True], idle) == [1]
    assert not idle.any()
