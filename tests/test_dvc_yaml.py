"""dvc.yaml is written by `ftfof dvc-yaml` (:mod:`ftfof.pipeline.dvcfile`): the committed file is
what the catalog and the import graph give, and the robot's stages stay in their own rooms."""

from __future__ import annotations

import pytest
import yaml
from typer.testing import CliRunner

from ftfof.pipeline.dvcfile import STAGES, code_deps, render
from ftfof.pipeline.imports import ROOT
from stages.cli import app

COMMITTED = (ROOT / "dvc.yaml").read_text()


def test_the_committed_dvc_yaml_is_the_generated_one():
    assert render() == COMMITTED, "dvc.yaml drifted: run `ftfof dvc-yaml`"


def test_the_check_flag_fails_on_a_drifted_file(tmp_path):
    drifted = tmp_path / "dvc.yaml"
    drifted.write_text(COMMITTED.replace("persist: true", "persist: false", 1))
    result = CliRunner().invoke(app, ["dvc-yaml", "--out", str(drifted), "--check"])
    assert result.exit_code == 1 and "stale" in result.output
    result = CliRunner().invoke(app, ["dvc-yaml", "--out", str(drifted)])
    assert result.exit_code == 0 and drifted.read_text() == COMMITTED


def covers(deps: list[str], path: str) -> bool:
    return any(path == d or path.startswith(d + "/") for d in deps)


def test_a_controller_change_stales_climb_and_slip_not_the_platform():
    """ftfof/climb/control is the climbs' code, and evaluate's platform runs do not import it."""
    stages = yaml.safe_load(COMMITTED)["stages"]
    control = "ftfof/climb/control/feedforward.py"
    stale = {name for name, s in stages.items() if covers(s["deps"], control)}
    assert stale == {"climb", "slip"}


def test_directories_are_listed_only_where_every_source_file_is_imported():
    """A folded directory is one whose every file the command imports; a sample's deps hold no
    training code."""
    deps = code_deps(STAGES["sample"].command)
    assert "ftfof/config" in deps and not any(d.startswith("ftfof/surrogate") for d in deps)
    for d in deps:
        assert (ROOT / d).exists(), d


def test_an_output_git_tracks_is_one_dvc_does_not_cache():
    """DVC refuses to cache a file git tracks ("already tracked by SCM"): each committed report
    is an uncached output (the refine report once was not, and a paper-scale run stopped)."""
    import subprocess

    tracked = set(subprocess.run(
        ["git", "ls-files", "reports", "data"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.split())  # fmt: skip
    stages = yaml.safe_load(COMMITTED)["stages"]
    for name, stage in stages.items():
        for entry in stage.get("outs", []):
            path, options = (entry, {}) if isinstance(entry, str) else next(iter(entry.items()))
            if path in tracked:
                assert options.get("cache") is False, f"{name}: {path} is in git and cached"


def test_every_param_a_stage_reads_is_in_params_yaml():
    """DVC stops a stage whose params key params.yaml lacks, even where the settings model has a
    default (the climb stage stopped on evaluate.climb once): each key, ${...} resolved, is
    there."""
    import re

    params = yaml.safe_load((ROOT / "params.yaml").read_text())

    def at(key: str) -> object:
        node: object = params
        for part in key.split("."):
            assert isinstance(node, dict) and part in node, f"params.yaml has no {key}"
            node = node[part]
        return node

    for stage in yaml.safe_load(COMMITTED)["stages"].values():
        for key in stage["params"]:
            at(re.sub(r"\$\{([\w.]+)\}", lambda m: str(at(m[1])), key))


def _modified(status: dict) -> dict[str, set[str]]:
    """Per stage, the dependencies `dvc status --json` calls modified."""
    out: dict[str, set[str]] = {}
    for name, entries in status.items():
        for entry in entries:
            if isinstance(entry, dict):
                deps = entry.get("changed deps", {})
                modified = {d for d, why in deps.items() if why == "modified"}
                out.setdefault(name, set()).update(modified)
    return out


@pytest.mark.integration
def test_dvc_status_after_a_controller_change_names_climb_and_slip_only(tmp_path):
    """`dvc status` on a clean copy with the committed dvc.lock, before and after a controller's
    source changes: the stages the change stales are climb and slip, not evaluate's platform
    runs (without outputs every stage also reports them missing, and a lock behind the code
    reports that code: both are there before the change too)."""
    import json

    from tests.pipeline import clone_to, run

    repo = clone_to(tmp_path)
    before = _modified(json.loads(run(repo, "dvc", "status", "--json").stdout))
    control = repo / "ftfof/climb/control/feedforward.py"
    control.write_text(control.read_text() + "\n# a change\n")
    after = _modified(json.loads(run(repo, "dvc", "status", "--json").stdout))
    stale = {name for name, deps in after.items() if deps - before.get(name, set())}
    assert stale == {"climb", "slip"}, after
