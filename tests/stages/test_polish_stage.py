"""Stage `polish` on the real platform (tiny sizes): the polished rows follow refine's front, the
optimum is one the simulator passed, a killed run resumes from its journal without simulating
a journalled batch again, and ``generations: 0`` passes refine's optimum on untouched."""

import copy
import json
import shutil

import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from ftfof.pipeline import jobs, simcheck
from ftfof.pipeline.polish import CONFIRM_ROW, FIRST_ROW, JOURNAL
from stages.cli import app
from tests.conftest import polish_args, tree_bytes, write_params
from tests.stages.conftest import TINY_POLISH

pytestmark = pytest.mark.integration

runner = CliRunner()


@pytest.fixture(scope="module")
def polished(refined_tiny):
    work, params, env, _, _ = refined_tiny
    result = runner.invoke(app, polish_args(params, work / "refine", work / "first"), env=env)
    assert result.exit_code == 0, result.output
    return work / "first"


def test_polished_rows_follow_refines_front_and_the_optimum_passed_the_check(
    refined_tiny, polished
):
    """What polish guarantees whatever the tiny search finds (its models differ by machine
    release, and its offspring may all break a rule): the journal accounts for every row the
    search simulated; refine's passed rows are measured without a simulation, so the optimum is
    polished and confirmed even when the search simulated nothing new."""
    work, *_ = refined_tiny
    before = pq.read_table(work / "refine" / "optimize" / "front.parquet").to_pandas()
    after = pq.read_table(polished / "optimize" / "front.parquet").to_pandas()
    report = json.loads(polished.with_suffix(".json").read_text())
    optimum = json.loads((polished / "optimize" / "optimum.json").read_text())
    # the journal holds every verdict: the search's (its own rows), then the confirmation's
    journal = [json.loads(line) for line in (polished / JOURNAL).read_text().splitlines()]
    verdicts = [v for entry in journal for v in entry["verdicts"]]
    search = [v for v in verdicts if FIRST_ROW <= v["row"] < CONFIRM_ROW]
    confirmed = [v for v in verdicts if v["row"] >= CONFIRM_ROW]
    assert len(search) + len(confirmed) == len(verdicts)
    assert report["simulated"] == len(search)
    assert report["refused"] == sum(not v["ok"] for v in search)
    assert report["polished"], report
    assert len(report["history"]) == TINY_POLISH["generations"]
    head = after.iloc[: len(before)]
    assert head.row.tolist() == before.row.tolist()
    assert head.origin.tolist() == before.origin.tolist()
    assert (after.origin.iloc[len(before) :] == "polish").all()
    assert len(after) - len(before) == len(report["front"]) >= 1
    assert optimum["origin"] == "polish" and optimum["front_row"] >= len(before)
    chosen = next(v for v in optimum["simulator_check"] if v["row"] == optimum["front_row"])
    # chosen on the confirmation: the nominal run and polish.confirm_copies fresh copies
    assert chosen["ok"] and chosen["runs"] == 5 == report["optimum"]["runs"]
    assert report["optimum"]["simulated"]["fs1"] == pytest.approx(chosen["simulated"][0], abs=1e-4)
    assert after.loc[after.row == optimum["front_row"], "recheck_feasible"].item()
    names = report["objectives"]  # the optimum as confirmed (5 runs) and as the search saw it
    assert any(
        v["ok"]
        and v["simulated"][0] == pytest.approx(report["optimum"]["simulated"][names[0]], abs=1e-4)
        for v in confirmed
    )
    start = [v for v in optimum["simulator_check"] if v["ok"] and v["row"] < len(before)]
    assert any(
        v["ok"]
        and v["simulated"][0] == pytest.approx(report["optimum"]["searched"][names[0]], abs=1e-4)
        for v in search + start
    )


def test_a_killed_run_resumes_from_its_journal(refined_tiny, polished, monkeypatch):
    work, params, env, _, _ = refined_tiny
    resumed = work / "resumed"
    shutil.copytree(polished, resumed)
    manifest = json.loads((resumed / "manifest.json").read_text())
    interrupted = {**manifest, "complete": False, "source": jobs.source()}
    (resumed / "manifest.json").write_text(json.dumps(interrupted))
    shutil.rmtree(resumed / "optimize")
    # the confirmation's batch is always the journal's last line, however many the search wrote
    lines = (resumed / JOURNAL).read_bytes().splitlines(keepends=True)
    assert lines
    cut = lines[-1][: len(lines[-1]) // 2]
    (resumed / JOURNAL).write_bytes(b"".join(lines[:-1]) + cut)  # killed mid-line
    asked = []
    check = simcheck.simulator_check_of

    def counting(*args):
        inner = check(*args)

        def counted(rows, X):
            asked.append(len(rows))
            return inner(rows, X)

        return counted

    monkeypatch.setattr(simcheck, "simulator_check_of", counting)
    result = runner.invoke(app, polish_args(params, work / "refine", resumed), env=env)
    assert result.exit_code == 0, result.output
    assert len(asked) == 1  # every whole batch was read back, the cut one simulated again
    assert tree_bytes(resumed) == tree_bytes(polished)


def test_no_generations_pass_refines_optimum_on(refined_tiny):
    work, _, env, data, _ = refined_tiny
    data = copy.deepcopy(data)
    data["polish"] = {**data["polish"], "generations": 0}
    params = write_params(work / "none.yaml", data)
    result = runner.invoke(app, polish_args(params, work / "refine", work / "none"), env=env)
    assert result.exit_code == 0, result.output
    assert tree_bytes(work / "none" / "optimize") == tree_bytes(work / "refine" / "optimize")
    assert json.loads((work / "none.json").read_text())["polished"] is False
