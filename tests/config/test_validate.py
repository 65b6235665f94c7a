"""A parsed settings document validated into Params, every problem one line naming its key."""

from __future__ import annotations

import pytest

from ftfof.config.validate import parse_params
from ftfof.errors import ParamsError


def test_the_repositorys_document_validates(params_dict):
    assert parse_params(params_dict).robot == params_dict["robot"]


def test_a_document_that_is_not_a_mapping_is_refused_by_its_source():
    with pytest.raises(ParamsError, match=r"edited\.yaml: must be a YAML mapping of sections"):
        parse_params(["robot"], "edited.yaml")


def test_each_problem_names_its_key_path_and_the_value_it_got(params_dict):
    params_dict["sample"]["n"] = "many"
    with pytest.raises(ParamsError) as err:
        parse_params(params_dict)
    assert "sample.n:" in str(err.value) and "(got 'many')" in str(err.value)
    params_dict["optimize"]["population"] = -1
    with pytest.raises(ParamsError, match=r"2 problems:\n  sample\.n: .*\n  optimize\.population"):
        parse_params(params_dict)


def test_a_proof_pull_needs_the_climber_it_is_the_demand_of(params_dict):
    robot = params_dict["robots"][params_dict["robot"]]
    robot["climber"] = None
    with pytest.raises(ParamsError, match=r"robots\.mst_m3f: proof: F_proof is the climbing"):
        parse_params(params_dict)
    robot["proof"] = None
    assert parse_params(params_dict).selected_robot.proof is None


def test_a_proof_hold_longer_than_the_stance_is_refused(params_dict):
    params_dict["platform"]["protocol"]["proof_hold"] = 3.5  # MST-M3F stands 3 x 1 s
    with pytest.raises(ParamsError, match=r"platform\.protocol\.proof_hold: 3\.5 s is longer"):
        parse_params(params_dict)
    params_dict["robots"][params_dict["robot"]]["proof"] = None  # no pull, no hold to judge
    parse_params(params_dict)
