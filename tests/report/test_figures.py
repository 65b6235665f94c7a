"""Figures name every surrogate target they can be asked to draw."""

from ftfof.data.targets import TARGETS, UNITS
from ftfof.report.figures import TITLES


def test_every_target_has_a_title_with_its_unit():
    assert set(TITLES) == set(TARGETS)
    for name in TARGETS:
        assert not UNITS[name] or f"[{UNITS[name]}" in TITLES[name].replace("²", "^2"), name
