"""Rules on the whole path: md on the path, and the hairpin guards that replace sampled fs6."""

import copy

import numpy as np
import pytest

from ftfof.config import Params
from ftfof.objectives import fs6_bending
from ftfof.pipeline.bench import context_of
from ftfof.trajectory.rules import (
    curvature_radius,
    md_path_violation,
    path_radius_violation,
    reversal_violation,
)
from tests.conftest import PUBLISHED_M3F

# Hand-made hairpin: its swing turns back at t = 0.35 s on a bend of a few micrometres. Every
# other rule passes, and fs6 passes on 256 samples (it fails on 31 or 64), like the first run's
# optimum.
HAIRPIN = np.array([0.1, 27.1, 30.3, 117.3, 140.1, 156.4, 12.3, 35.7, 39.1, 25.0, 12.6, 1.1]) / 1e3
# A draw the old policy kept: it moves forward fast at the start and is still 3.3 mm under
# hd = 9 mm past x = ld; every other rule passes.
CRAWLER = np.array([16.9, 92.9, 125.2, 127.5, 140.0, 140.2, 18.2, 42.4, 47.3, 51.3, 61.8, 29.0])
CRAWLER = CRAWLER / 1e3
DENSITIES = (31, 64, 256, 1000)


def _policy(raw_params, n_t=256, robot="mst_m3f", **constraints):
    data = copy.deepcopy(raw_params)
    data["robot"] = robot
    data["feasibility"]["n_t"] = n_t
    data["robots"][robot]["constraints"].update(constraints)
    return context_of(Params.model_validate(data)).policy


def _circle(radius, turns, n):
    """Unit-speed-per-radian circle: position, velocity, acceleration (1, n, 2) and t."""
    t = np.linspace(0.0, 2 * np.pi * turns, n)
    c, s = np.cos(t), np.sin(t)
    pos = radius * np.stack([c, s], -1)[None]
    return pos, radius * np.stack([-s, c], -1)[None], radius * np.stack([-c, -s], -1)[None], t


# --- the functions, on hand-made inputs -----------------------------------------------------


def test_md_path_measures_depth_inside_the_forbidden_quadrant():
    t = np.linspace(0.0, 1.0, 5)  # detachment t <= 0.5
    crawl = np.array([[[0.0, 0.0], [0.02, 0.002], [0.05, 0.004], [0.1, 0.0], [0.2, 0.0]]])
    lifted = np.array([[[0.0, 0.0], [0.001, 0.01], [0.05, 0.02], [0.1, 0.0], [0.2, 0.0]]])
    v = md_path_violation(np.concatenate([crawl, lifted]), t, 0.5, ld=0.0045, hd=0.009)
    assert v[0] == pytest.approx(0.009 - 0.002)  # the lower of the two detachment points
    assert v[1] < 0  # after t = 0.5 the path may go back to the wall


def test_md_path_is_vacuous_for_a_vertical_lift_at_ld_zero():
    t = np.linspace(0.0, 1.0, 11)
    lift = np.stack([np.zeros(11), np.linspace(0, 0.03, 11)], -1)[None]
    assert md_path_violation(lift, t, 1.0, ld=0.0, hd=0.019)[0] <= 0


def test_curvature_radius_of_a_circle_a_line_and_a_stop():
    _, v, a, _ = _circle(0.004, 0.5, 50)
    np.testing.assert_allclose(curvature_radius(v, a), 0.004)
    line = np.tile([1.0, 2.0], (1, 5, 1))
    assert np.all(np.isinf(curvature_radius(line, 3 * line)))
    assert curvature_radius(np.zeros((1, 1, 2)), np.ones((1, 1, 2)))[0, 0] == 0.0


@pytest.mark.parametrize("n", DENSITIES)
def test_path_radius_judges_the_middle_of_the_path_not_its_ends(n):
    _, v, a, t = _circle(0.001, 3.0, n)  # 18.8 mm of path at 1 mm radius
    assert path_radius_violation(v, a, t, 0.002)[0] == pytest.approx(0.5)
    assert path_radius_violation(v, a, t, 0.0005)[0] == 0.0
    assert path_radius_violation(v, a, t, 0.01)[0] == 0.0  # shorter than two 10 mm end zones


def test_reversal_flags_a_straight_back_and_forth_and_skips_standstills():
    there_and_back = np.array([[[0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [-1.0, 0.0], [0.0, 0.0]]])
    assert reversal_violation(there_and_back, 1e-9)[0] == pytest.approx(1.0)
    forward = np.array([[[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.0]]])
    assert reversal_violation(forward, 1e-9)[0] <= 0


# --- in the policy ----------------------------------------------------------------------------


@pytest.mark.parametrize("n_t", DENSITIES)
def test_published_m3f_optimum_passes_every_rule_at_any_density(raw_params, n_t):
    policy = _policy(raw_params, n_t)
    names = {c.name for c in policy.constraints}
    assert {"md_path", "min_path_radius", "no_cusp", "fs6 = 0"} <= names
    report = policy.check(PUBLISHED_M3F)
    assert report.feasible[0], report.failed(0)


def test_hairpin_passes_old_fs6_on_256_samples(m3f):
    policy = m3f.policy
    assert fs6_bending(policy.sample(HAIRPIN[None]).position, 1e-9)[0] == 0.0
    old = tuple(c for c in policy.constraints if c.name not in ("min_path_radius", "no_cusp"))
    assert policy.check(HAIRPIN, constraints=old).feasible[0]


@pytest.mark.parametrize("n_t", DENSITIES)
def test_hairpin_fails_the_bend_rule_at_any_density(raw_params, n_t):
    policy = _policy(raw_params, n_t)
    bend = tuple(c for c in policy.constraints if c.name in ("min_path_radius", "no_cusp"))
    report = policy.check(HAIRPIN, constraints=bend)
    assert any(f.startswith("bending: min_path_radius") for f in report.failed(0))


def test_md_path_rejects_a_crawl_by_name_and_can_be_switched_off(raw_params):
    on = _policy(raw_params)
    failed = [f.split(" (by")[0] for f in on.check(CRAWLER).failed(0)]
    # the crawl also outruns the leg's joints: that rule is the leg's, not md_path's
    assert [f for f in failed if not f.startswith("joint_limit")] == ["min_detachment: md_path"]
    off = _policy(raw_params, md_path=False)
    assert "md_path" not in {c.name for c in off.constraints}
    assert all(f.startswith("joint_limit") for f in off.check(CRAWLER).failed(0))


def test_fine_recheck_names_md_path(raw_params):
    """The optimize stage rechecks the front with the same policy on a finer grid."""
    fine = _policy(raw_params, n_t=4096)
    assert any(f.startswith("min_detachment: md_path") for f in fine.check(CRAWLER).failed(0))
