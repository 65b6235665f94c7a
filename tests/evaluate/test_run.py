"""The evaluation's pieces on synthetic frames: front sampling, failure policy, Table I rows."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ftfof.data.dataset import CHANNELS
from ftfof.errors import SimulationError
from ftfof.evaluate.film_check import FilmCheck
from ftfof.evaluate.members import front_members
from ftfof.evaluate.run import Inputs, front_sample
from ftfof.evaluate.runs import OPTIMUM, PAPER_OPTIMUM, ok_rows, table_rows
from ftfof.evaluate.table import COLUMNS, table_one
from ftfof.rules import FootRules
from ftfof.sim.film import FilmLimit
from tests.data.fake import fake_channels

T3 = 1.0  # the fake samples' trajectory time


def _with_channels(frame: pd.DataFrame, pulls: list[float]) -> pd.DataFrame:
    """Full-rate channels per row: a fake sample whose pull (and release ringing) is ``pulls``."""
    series = [fake_channels(p) for p in pulls]
    return frame.assign(**{c: [ch[c] for ch in series] for c in CHANNELS})


def _inputs(
    n: int, chosen: int, infeasible: tuple[int, ...] = (), nominated: tuple[int, ...] = ()
) -> Inputs:
    front = pd.DataFrame(
        {
            "recheck_feasible": [i not in infeasible for i in range(n)],
            "origin": ["refine:1" if i in nominated else "front" for i in range(n)],
        },
        index=pd.Index(range(n), name="row"),
    )
    return Inputs({"front_row": chosen}, front, ["fs1"], "digest")


def test_front_sample_spreads_over_passing_rows_and_leaves_out_the_optimum():
    inputs = _inputs(10, chosen=0, infeasible=(5,))
    rows = front_sample(inputs, 3)
    assert rows == [1, 6, 9]
    assert front_sample(inputs, 0) == []
    assert front_sample(inputs, 50) == [1, 2, 3, 4, 6, 7, 8, 9]


def test_front_sample_leaves_out_nominees_simulated_before():
    inputs = _inputs(8, chosen=7, nominated=(6, 7))
    assert front_sample(inputs, 50) == [0, 1, 2, 3, 4, 5]


def _simulations(status: str = "ok") -> pd.DataFrame:
    peaks = {"peak_detachment": [2.0, 1.0], "peak_pre_pressure": [4.0, 2.0]}
    foot = {c: [1.0, 1.0] for c in ("peak_pull", "peak_normal", "peak_shear", "min_bend_radius")}
    foot["landing_pre_pressure"] = [5.0, 5.0]
    frame = pd.DataFrame(
        {
            "source": ["baseline:polynomial", OPTIMUM],
            "status": ["ok", status],
            "error": ["", "boom" if status != "ok" else ""],
            "peak_body_acc": [1.0, 1.0],
            **peaks,
            **foot,
        }
    )
    return _with_channels(frame, [4.0, 2.0])


def test_ok_rows_names_a_failed_optimum():
    with pytest.raises(SimulationError, match="boom"):
        ok_rows(_simulations("failed"), "polynomial")
    with pytest.raises(SimulationError, match="missing"):
        ok_rows(_simulations(), "cycloidal")


def test_table_rows_compare_the_optimum_with_the_reference():
    rows = {
        r.trajectory: r for r in table_rows(ok_rows(_simulations(), "polynomial"), "polynomial", T3)
    }
    assert list(rows) == ["polynomial", OPTIMUM]
    assert rows[OPTIMUM].change["peak_detachment"] == pytest.approx(-50.0)
    assert rows["polynomial"].change["peak_pre_pressure"] == 0
    # the detachment-window jitter: the release ringing (3x the pull, on a 2 m/s² floor)
    assert rows["polynomial"].values["jitter"] == pytest.approx(2.0 + 12.0, rel=1e-3)
    assert rows[OPTIMUM].change["jitter"] == pytest.approx(100 * (8.0 - 14.0) / 14.0, rel=1e-3)


def test_front_members_show_each_trade_and_the_film_verdict():
    sims = _simulations().assign(source=[OPTIMUM, "front"], sample_id=[7, 3])
    sims["min_bend_radius"] = [0.0065, 0.0042]
    sims["landing_pre_pressure"] = [5.5, 4.0]
    sims["max_clearance"] = [0.03, 0.0015]
    sims["switch_time"] = [0.3, float("nan")]  # the second never let go
    sims["Fp"] = [np.where(t > 1.0, 5.2, 0.0) for t in sims["t"]]  # the first holds 5.2 N
    sims["peak_body_acc"] = [8.0, 12.0]
    film = FilmLimit(fc=0.006, peel_root=0.0058)
    # on the check film the optimum bends to 5.9 mm: past fc there, though not on 40 elements
    films = FilmCheck(40, 80, 0.006, {"optimum": 0.0065, "front 3": 0.0042}, {"optimum": 0.0059})
    rules = FootRules(
        film=film,
        swing_clearance=0.009,
        detached=0.002,
        landing_start=0.6,
        pre_pressure=5.0,
        landing_tolerance=0.15,
        retouch_allowed=None,
        landing_hold=0.25,
        body_acc_limit=9.81,
    )
    out = front_members(sims, T3, rules, films)
    first, other = out["members"]
    assert first["optimum"] and first["row"] == 7 and first["film_safe"]
    assert first["min_bend_radius_on_check_film"] == 0.0059
    assert first["film_safe_on_check_film"] is False
    assert other["row"] == 3 and not other["film_safe"]
    assert other["film_safe_on_check_film"] is None  # not simulated on the check film
    assert films.as_dict()["keeps_fc_only_at_nodes"] == ["optimum"]
    assert films.as_dict()["missing"] == ["front 3"]
    assert other["landing_pre_pressure_error"] == pytest.approx(1.0)
    assert out["film_safe_fraction"] == 0.5 and out["film_limit"]["limit"] == 0.006
    assert first["lets_go"] and not other["lets_go"] and out["lets_go_fraction"] == 0.5
    assert other["release_fault"] == "the pad never let go"
    assert first["lands"] and not other["lands"] and out["lands_fraction"] == 0.5  # 5.5 / 4.0 N
    assert other["landing_fault"] == "the landing pressed 4.00 N, outside a = 5.00 N ± 15 %"
    assert first["calm"] and not other["calm"] and out["calm_fraction"] == 0.5
    assert other["shake_fault"] == "the body shook 12.0 m/s², above the robot's 9.81 m/s² limit"
    assert first["clean"] and not other["clean"] and out["clean_fraction"] == 0.5


def test_the_table_lists_the_reference_then_baselines_then_the_paper_optimum_then_ours():
    figures = {
        c: [1.0] * 6
        for c in ("peak_pre_pressure", "peak_body_acc", "peak_normal", "landing_pre_pressure")
    }
    sources = ["cycloidal", "eps_bezier", "polynomial", "random_bezier"]  # as a table sorts them
    sims = pd.DataFrame(
        {
            "source": [OPTIMUM, PAPER_OPTIMUM, *(f"baseline:{s}" for s in sources)],
            "status": ["ok"] * 6,
            "error": [""] * 6,
            "peak_detachment": [1.0, 1.5, 2.5, 2.2, 2.0, 2.1],
            "peak_pull": [1.2, 1.6, 2.6, 2.3, 2.4, 2.2],
            "peak_shear": [0.5] * 6,
            "min_bend_radius": [0.006, 0.01, 0.004, 0.003, 0.003, 0.003],
            **figures,
        }
    )
    rows = table_rows(ok_rows(_with_channels(sims, [1.0] * 6), "polynomial"), "polynomial", T3)
    assert [r.trajectory for r in rows] == [
        "polynomial",
        "cycloidal",
        "random_bezier",
        "eps_bezier",
        "paper_optimum",
        OPTIMUM,
    ]
    ours = rows[-1]
    assert ours.change["peak_pull"] == pytest.approx(-50.0)
    assert ours.change["min_bend_radius"] == pytest.approx(100.0)  # bent twice as gently
    assert set(ours.values) >= {"peak_pull", "peak_normal", "peak_shear", "min_bend_radius"}


def test_mst_q_cannot_run_the_common_arcs_and_its_reference_is_one_it_can(mst_q, params):
    """FTFOF §VII: the polynomial and the cycloid lift along an arc from the first instant;
    MST-Q must detach straight up. Its Table I is taken against a baseline it can run."""
    from ftfof.evaluate.feasible import admitted, reference_for
    from ftfof.report.summary import tables
    from ftfof.seeds import seed_for
    from ftfof.trajectory.baselines import common_trajectories

    baselines = common_trajectories(
        mst_q.policy, params.baselines, seed_for(params.base.seed, "baselines")
    )
    breaks = admitted(mst_q, baselines, {})
    assert any("md_path" in rule for rule in breaks["polynomial"])
    assert any("md_path" in rule for rule in breaks["cycloidal"])
    assert breaks["random_bezier"] == []  # the robot's own sampler drew it
    detachment = {"polynomial": 7.0, "cycloidal": 6.0, "random_bezier": 8.0, "eps_bezier": 5.0}
    reference, why = reference_for("polynomial", None, breaks, detachment)
    assert reference == "random_bezier" and why.startswith("polynomial breaks the robot's rules")
    assert reference_for("polynomial", "cycloidal", breaks, detachment)[0] == "cycloidal"
    rows = table_one(
        {n: dict.fromkeys(("peak_detachment", "peak_pre_pressure", "peak_body_acc"), 1.0)
         | dict.fromkeys(("peak_pull", "peak_normal", "peak_shear", "jitter"), 1.0)
         | {"landing_pre_pressure": 5.0, "min_bend_radius": 0.007}
         for n in ("random_bezier", "polynomial")},
        "random_bezier",
        COLUMNS,
    )  # fmt: skip
    first, _ = tables(rows, "random_bezier", 5.0, breaks)
    runs = {r["trajectory"]: r["runs"] for r in first["rows"]}
    assert runs["random_bezier"] == "yes" and runs["polynomial"].startswith("no: min_detachment")
