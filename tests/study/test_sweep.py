"""Sweeps: axes parsed strictly, the product planned with every setting named, the queue's
command and status, the key columns."""

import pytest

from ftfof.errors import ParamsError
from ftfof.study.sweep import (
    check_presets,
    failed,
    key_columns,
    parse_axes,
    plan,
    queue_args,
    unfinished,
)


def test_the_product_names_every_setting_in_every_experiment():
    experiments = plan(parse_axes(["robots=mst_m3f,mst_q", "surfaces=acrylic,glass"]), "s1-")
    assert [e.name for e in experiments] == [
        "s1-mst_m3f-acrylic",
        "s1-mst_m3f-glass",
        "s1-mst_q-acrylic",
        "s1-mst_q-glass",
    ]
    assert experiments[3].params == {
        "robot": "mst_q", "surface": "glass", "train.alias": "exp-s1-mst_q-glass"
    }  # fmt: skip


def test_an_experiment_registers_under_its_own_valid_alias():
    """The registry is shared: an experiment moving `champion` would make the workspace's next
    `dvc repro` refuse its own models."""
    from ftfof.config import Train

    (experiment,) = plan(parse_axes(["seeds=1"]), "1.5")
    assert experiment.alias == "exp-1-5seed1" != Train().alias
    Train(alias=experiment.alias)  # a valid train.alias


def test_a_seed_sweep_sets_the_search_seed_only():
    experiments = plan(parse_axes(["seeds=1,2,3"]))
    assert [e.name for e in experiments] == ["seed1", "seed2", "seed3"]
    assert experiments[1].settings == {"base.search_seed": "2"}
    check_presets(parse_axes(["seeds=4"]), {"robot": ["mst_q"], "surface": ["glass"]})


def test_the_search_seed_defaults_to_the_base_seed(raw_params):
    from ftfof.config import Params

    data = {**raw_params, "base": {"seed": 7}}
    assert Params.model_validate(data).search_seed == 7
    data["base"] = {"seed": 7, "search_seed": 3}
    assert Params.model_validate(data).search_seed == 3


@pytest.mark.parametrize(
    ("tokens", "message"),
    [
        (["robot=mst_q"], "expected one of robots, surfaces, seeds"),
        (["seeds=1,x"], "seeds must be non-negative integers"),
        (["robots=a,,b"], "non-empty and distinct"),
        (["robots=a,a"], "non-empty and distinct"),
        (["robots=a b"], "not a usable experiment name part"),
        (["robots=a", "robots=b"], "robots given twice"),
        ([], "nothing to sweep"),
    ],
)
def test_malformed_axes_are_refused_with_the_token_at_fault(tokens, message):
    with pytest.raises(ParamsError, match=message):
        parse_axes(tokens)


def test_an_unknown_preset_is_named_with_the_known_ones():
    axes = parse_axes(["surfaces=acrylic,teflon"])
    with pytest.raises(ParamsError, match="no surface preset 'teflon' \\(have acrylic, glass\\)"):
        check_presets(axes, {"surface": ["acrylic", "glass"], "robot": []})


SUMMARY = "reports/summary/evaluate.json"


def test_a_finished_sweep_prints_its_key_columns_only():
    def experiment(name, robot, pull, change, search_seed=None):
        return {
            "name": name,
            "rev": "0" * 40,
            "data": {
                "params": {"params.yaml": {"data": {
                    "robot": robot, "surface": "glass",
                    "base": {"seed": 7, "search_seed": search_seed},
                }}},
                "metrics": {"reports/summary/evaluate.json": {"data": {
                    "reference": "polynomial",
                    "optimum": {"peak_pull": pull, "peak_pull_change": change},
                }}},
            },
        }  # fmt: skip

    shown = [
        {
            "name": "main",
            "data": {},
            "experiments": [{"revs": [experiment("s-mst_q-glass", "mst_q", 6.5, -4.04, 3)]}],
        },
        experiment("s-mst_m3f-glass", "mst_m3f", 7.1, 1.0),
    ]
    table = key_columns(shown, ["s-mst_m3f-glass", "s-mst_q-glass"], SUMMARY).splitlines()[2:]
    assert table[0].startswith("| experiment | robot | surface | seed | search seed | reference |")
    assert table[2] == (
        "| s-mst_m3f-glass | mst_m3f | glass | 7 | - | polynomial | 7.1 (+1.0 %) | ? | ? | ? |"
    )
    assert table[3].startswith(
        "| s-mst_q-glass | mst_q | glass | 7 | 3 | polynomial | 6.5 (-4.0 %)"
    )
    assert len(table) == 4 and all(len(line) < 200 for line in table)


def test_an_experiment_is_queued_with_every_setting_and_its_alias():
    experiments = plan(parse_axes(["robots=mst_m3f,mst_q", "surfaces=acrylic,glass"]), "s1-")
    assert queue_args(experiments[3]) == [
        "exp", "run", "--queue", "-n", "s1-mst_q-glass", "-S", "robot=mst_q", "-S", "surface=glass",
        "-S", "train.alias=exp-s1-mst_q-glass",
    ]  # fmt: skip
    (seed,) = plan(parse_axes(["seeds=2"]))
    assert queue_args(seed)[-4:-2] == ["-S", "base.search_seed=2"]


STATUS = """Task     Name          Created    Status
0a1b2c3  mst_q-glass   10:02 AM   Running
4d5e6f7  mst_m3f-glass 10:02 AM   Queued
8a9b0c1  other         09:00 AM   Failed
2d3e4f5  mst_q-acryl   10:02 AM   Failed
Worker status: 1 active, 0 idle
"""


def test_queue_status_is_read_for_the_sweeps_own_experiments_only():
    names = ["mst_q-glass", "mst_m3f-glass", "mst_q-acryl"]
    assert unfinished(STATUS, names) == ["mst_q-glass", "mst_m3f-glass"]
    assert failed(STATUS, names) == ["mst_q-acryl"]
