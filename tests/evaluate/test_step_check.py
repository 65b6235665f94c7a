"""Table I's figures at two solver steps: changes against the reference at each, how far the
optimum's moved, and runs that failed at one step."""

import pytest

from ftfof.evaluate.step_check import CHECKED, LOWER_IS_BETTER, step_check

NAMES = [c for c, _, _ in CHECKED]


def _figures(pull: float, jitter: float, force: float, landing: float) -> dict[str, float]:
    return dict(zip(NAMES, (pull, jitter, force, landing), strict=True))


AT_STEP = {"polynomial": _figures(7.0, 8.0, 10.0, 5.4), "optimum": _figures(6.0, 4.0, 5.0, 5.0)}
AT_CHECK = {"optimum": _figures(6.0, 6.0, 16.0, 5.3), "polynomial": _figures(7.0, 10.0, 20.0, 5.4)}


def test_changes_are_taken_at_each_step_and_the_shift_is_their_difference():
    check = step_check(AT_STEP, AT_CHECK, "polynomial", 5e-4, 1.25e-4)
    assert [r.trajectory for r in check.at_check] == ["polynomial", "optimum"]  # at_step's order
    shift = check.shift("optimum")
    # jitter -50 % -> -40 %: 10 points of the advantage were the step's; fs7 -50 % -> -20 %
    assert shift == pytest.approx({"peak_pull": 0.0, "jitter": 10.0, "force_jitter": 30.0})
    # the landing press is scored by its distance from a: its change is no advantage to shift
    assert "landing_pre_pressure" not in shift and set(shift) == set(LOWER_IS_BETTER)
    record = check.as_dict("optimum")
    assert record["step"] == 5e-4 and record["check_step"] == 1.25e-4 and record["missing"] == []
    assert record["table"]["optimum"]["jitter"] == [4.0, 6.0]
    assert record["table"]["optimum"]["jitter_change"] == [-50.0, -40.0]
    assert record["table"]["optimum"]["landing_pre_pressure"] == [5.0, 5.3]
    assert record["table"]["polynomial"]["force_jitter_change"] == [0.0, 0.0]


def test_a_run_missing_at_one_step_is_left_out_and_named():
    at_step = {**AT_STEP, "paper_optimum": _figures(7.5, 11.0, 25.0, 4.7)}
    check = step_check(at_step, AT_CHECK, "polynomial", 5e-4, 1.25e-4)
    assert check.missing == ["paper_optimum"]
    assert [r.trajectory for r in check.at_step] == ["polynomial", "optimum"]
    assert check.shift("optimum")["jitter"] == pytest.approx(10.0)


def test_without_the_reference_at_both_steps_nothing_is_compared():
    check = step_check(AT_STEP, {"optimum": AT_CHECK["optimum"]}, "polynomial", 5e-4, 1.25e-4)
    assert check.missing == ["polynomial"] and check.at_step == [] and check.at_check == []
    record = check.as_dict("optimum")
    assert record["table"] == {} and record["shift"] == {}


def test_the_check_runs_at_one_step_throughout_under_its_own_key(params):
    from ftfof.evaluate.specs import with_step
    from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
    from ftfof.sim.spec import baseline_specs

    ctx = context_of(params)
    (spec,) = baseline_specs(bench(params, ctx), baseline_trajectories(params, ctx), ["polynomial"])
    fine = with_step(spec, 1.25e-4)
    assert fine.solver.step == fine.solver.free_step == 1.25e-4
    assert fine.key == "fine:baseline:polynomial:0" and fine.source == "fine:baseline:polynomial"
    assert fine.seed == spec.seed and fine.trajectory is spec.trajectory
    assert spec.solver.step == params.acquire.solver.step  # the original is untouched
