"""A failing simulation becomes a failed result with the reason; the others go on."""

from ftfof.sim.pool import run_all
from ftfof.sim.records import FailureReason
from tests.sim.helpers import PUBLISHED, bench


def test_absurd_stiffness_fails_with_exudyns_message_and_the_rest_go_on(params):
    good = bench(params).bezier("sampled", 0, PUBLISHED)
    absurd = bench(params, surface={"contact_stiffness": 1e30}).bezier("sampled", 1, PUBLISHED)
    bad, fine = run_all([absurd, good], workers=2)
    assert bad.status == "failed" and bad.key == "sampled:1"
    assert "Error" in bad.error or "stopped early" in bad.error
    assert fine.ok and fine.scalars["peak_detachment"] > 0


def test_a_run_over_its_time_budget_is_stopped_and_failed(params):
    spec = bench(params, solver={"time_budget": 0.05}).bezier("sampled", 0, PUBLISHED)
    (result,) = run_all([spec], workers=1)
    assert result.status == "failed"
    assert "time budget" in result.error
    assert result.reason is FailureReason.TIME_BUDGET and result.scalars["retries"] == 0
    assert len(result.channels["t"]) > 0  # partial channels kept for diagnosis
