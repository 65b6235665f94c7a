"""Table I's figures at two solver steps: changes against the reference at each, and how far the
optimum's moved."""

import pytest

from ftfof.evaluate.step_check import CHECKED, step_check

NAMES = [c for c, _, _ in CHECKED]


def _figures(pull: float, jitter: float, force: float, landing: float) -> dict[str, float]:
    return dict(zip(NAMES, (pull, jitter, force, landing), strict=True))


AT_STEP = {"polynomial": _figures(7.0, 8.0, 10.0, 5.4), "optimum": _figures(6.0, 4.0, 5.0, 5.0)}
AT_CHECK = {"optimum": _figures(6.0, 6.0, 16.0, 5.0), "polynomial": _figures(7.0, 10.0, 20.0, 5.4)}


def test_changes_are_taken_at_each_step_and_the_shift_is_their_difference():
    check = step_check(AT_STEP, AT_CHECK, "polynomial", 5e-4, 1.25e-4)
    assert [r.trajectory for r in check.at_check] == ["polynomial", "optimum"]  # at_step's order
    shift = check.shift("optimum")
    # jitter -50 % -> -40 %: 10 points of the advantage were the step's; fs7 -50 % -> -20 %
    assert shift["jitter"] == pytest.approx(10.0)
    assert shift["force_jitter"] == pytest.approx(30.0)
    assert shift["peak_pull"] == pytest.approx(0.0)
    record = check.as_dict("optimum")
    assert record["step"] == 5e-4 and record["check_step"] == 1.25e-4
    assert record["table"]["optimum"]["jitter"] == [4.0, 6.0]
    assert record["table"]["optimum"]["jitter_change"] == [-50.0, -40.0]
    assert record["table"]["polynomial"]["force_jitter_change"] == [0.0, 0.0]


def test_runs_missing_at_one_step_are_named():
    with pytest.raises(ValueError, match="paper_optimum"):
        step_check(
            {**AT_STEP, "paper_optimum": _figures(7.5, 11.0, 25.0, 4.7)},
            AT_CHECK,
            "polynomial",
            5e-4,
            1.25e-4,
        )
