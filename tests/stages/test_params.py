"""params.yaml validation: bad keys, types and values fail with one line naming the key."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

from ftfof.errors import ParamsError
from ftfof.pipeline.params_file import load_params
from stages.cli import app
from tests.conftest import ROOT, write_params

runner = CliRunner()


def test_repository_params_validate():
    params = load_params(ROOT / "params.yaml")
    assert params.robot == "mst_m3f"
    assert set(params.robots) >= {"mst_m3f", "mst_q"}


def _error(tmp_path: Path, data: dict) -> str:
    with pytest.raises(ParamsError) as err:
        load_params(write_params(tmp_path / "params.yaml", data))
    return str(err.value)


def test_unknown_key_is_named(tmp_path, params_dict):
    params_dict["robots"]["mst_m3f"]["foot"]["pad_lenght"] = 0.05
    msg = _error(tmp_path, params_dict)
    assert "robots.mst_m3f.foot.pad_lenght: Extra inputs are not permitted (got 0.05)" in msg


def test_wrong_type_is_named(tmp_path, params_dict):
    params_dict["sample"]["n"] = "many"
    msg = _error(tmp_path, params_dict)
    assert "sample.n: Input should be a valid integer" in msg and "(got 'many')" in msg


def test_negative_length_is_named(tmp_path, params_dict):
    params_dict["robots"]["mst_m3f"]["foot"]["pad_length"] = -0.05
    msg = _error(tmp_path, params_dict)
    assert "robots.mst_m3f.foot.pad_length: Input should be greater than 0 (got -0.05)" in msg


def test_every_problem_is_listed_one_per_line(tmp_path, params_dict):
    params_dict["sample"]["n"] = "many"
    params_dict["robots"]["mst_m3f"]["foot"]["pad_length"] = -0.05
    params_dict["train"]["epochs"] = 0
    lines = _error(tmp_path, params_dict).splitlines()
    assert lines[0].endswith("3 problems:")
    assert sorted(line.strip().split(":")[0] for line in lines[1:]) == [
        "robots.mst_m3f.foot.pad_length",
        "sample.n",
        "train.epochs",
    ]


def test_unknown_robot_is_named(tmp_path, params_dict):
    params_dict["robot"] = "mst_x"
    assert "robot: 'mst_x' is not a preset (have mst_m3f, mst_q)" in _error(tmp_path, params_dict)


def test_a_pad_too_weak_in_shear_to_hold_the_robot_is_named(tmp_path, params_dict):
    """Three stance feet must hold the robot's weight on a wall with safety factor 2."""
    params_dict["robots"]["mst_m3f"]["platform"]["body"]["mass"] = 5.0  # ten times heavier
    msg = _error(tmp_path, params_dict)
    assert "surfaces.acrylic.shear_capacity_ratio: 2 is below" in msg
    assert "robot 'mst_m3f'" in msg and "safety factor 2" in msg


def test_a_shear_ratio_without_its_source_is_named(tmp_path, params_dict):
    del params_dict["surfaces"]["acrylic"]["shear_source"]
    assert "surfaces.acrylic.shear_source: Field required" in _error(tmp_path, params_dict)


def test_a_dataset_base_that_ends_inside_the_landing_hold_is_named(tmp_path, params_dict):
    params_dict["dataset"]["hold"] = 0.1
    msg = _error(tmp_path, params_dict)
    assert "dataset.hold: 0.1 s ends inside the landing hold" in msg and "fs3" in msg


def test_a_check_step_not_finer_than_the_acquisition_step_is_named(tmp_path, params_dict):
    params_dict["evaluate"]["check_step"] = params_dict["acquire"]["solver"]["step"]
    msg = _error(tmp_path, params_dict)
    assert "evaluate.check_step: 0.0005 s is not finer than acquire.solver.step" in msg


def test_a_check_film_not_finer_than_the_acquisition_film_is_named(tmp_path, params_dict):
    params_dict["evaluate"]["check_nodes"] = params_dict["acquire"]["solver"]["nodes"]
    msg = _error(tmp_path, params_dict)
    assert "evaluate.check_nodes: 40 film elements are not finer than acquire.solver.nodes" in msg


def test_a_film_too_thick_to_survive_its_fc_is_named(tmp_path, params_dict):
    """PET 250 um strains its outer fibre 2.08 % at fc = 6 mm, past its 2 % yield."""
    params_dict["robots"]["mst_m3f"]["platform"]["film"]["thickness"] = 0.00025
    msg = _error(tmp_path, params_dict)
    assert (
        "robots.mst_m3f: platform.film.thickness 250 um bent to foot.film_min_bend_radius 6 mm"
        " strains its outer fibre 2.08 %, past platform.film.yield_strain 2 %" in msg
    )


def test_unordered_timing_is_named(tmp_path, params_dict):
    params_dict["robots"]["mst_q"]["timing"] = {"T1": 0.5, "T2": 0.4, "T3": 1.0}
    assert "robots.mst_q.timing: must satisfy T1 < T2 < T3" in _error(tmp_path, params_dict)


def test_a_use_loss_that_is_not_trained_is_named(tmp_path, params_dict):
    params_dict["train"].update(losses=["mse"], use="dilate")
    assert "train: use 'dilate' must be one of losses ['mse']" in _error(tmp_path, params_dict)


def test_a_near_front_target_not_read_by_its_peak_is_named(tmp_path, params_dict):
    """fs2 reads the pull's mean: a local GP of its peak would change what fs2 reads."""
    params_dict["refine"]["near_front_peaks"] = ["Fp", "pull"]
    msg = _error(tmp_path, params_dict)
    assert "refine.near_front_peaks.1" in msg and "'body_acc'" in msg, msg


def test_a_near_front_peak_needs_no_broad_peak_model(params_dict, tmp_path):
    params_dict["train"]["peaks"] = ["jitter"]
    params_dict["refine"]["near_front_peaks"] = ["Fp", "body_acc"]
    params = load_params(write_params(tmp_path / "params.yaml", params_dict))
    assert params.refine.near_front_peaks == ["Fp", "body_acc"]


def test_polishing_more_objectives_than_the_robot_has_is_named(tmp_path, params_dict):
    params_dict["polish"] = {"priorities": 7}
    msg = _error(tmp_path, params_dict)
    assert "polish.priorities: 7 is more than robot 'mst_m3f''s 6 objectives" in msg


def test_a_polish_weighing_a_spread_it_has_not_measured_is_named(tmp_path, params_dict):
    params_dict["optimize"]["verify_copies"] = 0
    params_dict["polish"]["risk_sigmas"] = 1.0
    msg = _error(tmp_path, params_dict)
    assert "polish.risk_sigmas: 1 weighs the spread" in msg and "verify_copies is 0" in msg, msg
    params_dict["polish"]["risk_sigmas"] = 0.0
    params = load_params(write_params(tmp_path / "params.yaml", params_dict))
    assert params.polish.risk_sigmas == 0.0


def test_unknown_leg_type_is_named(tmp_path, params_dict):
    params_dict["robots"]["mst_q"]["leg"]["type"] = "hexapod"
    msg = _error(tmp_path, params_dict)
    assert "robots.mst_q.leg: Input tag 'hexapod' found using 'type' does not match" in msg


def test_a_leg_key_is_named_without_the_leg_type_tag(tmp_path, params_dict):
    params_dict["robots"]["mst_q"]["leg"]["joint_limits"][1] = [1.5, -1.0]
    msg = _error(tmp_path, params_dict)
    assert "robots.mst_q.leg.joint_limits.1: must be an increasing pair" in msg


def test_invalid_yaml_names_the_line(tmp_path):
    path = tmp_path / "params.yaml"
    path.write_text("base:\n  seed: 1\nrobot: [unclosed\n")
    with pytest.raises(ParamsError, match=r"params.yaml:\d+: not valid YAML"):
        load_params(path)


@pytest.mark.parametrize(
    "edit",
    [
        lambda d: d["robots"]["mst_m3f"]["foot"].update(pad_lenght=0.05),
        lambda d: d["sample"].update(n="many"),
        lambda d: d["robots"]["mst_m3f"]["foot"].update(pad_length=-0.05),
    ],
    ids=["unknown-key", "wrong-type", "negative-length"],
)
def test_bad_params_exit_non_zero_with_one_line_and_no_output(tmp_path, params_dict, edit):
    edit(params_dict)
    path = write_params(tmp_path / "params.yaml", params_dict)
    out = tmp_path / "traj.parquet"
    result = runner.invoke(app, ["sample", "-p", str(path), "--out", str(out)])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert not out.exists()
