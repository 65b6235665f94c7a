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
