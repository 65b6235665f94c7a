"""dvc.yaml, written from the catalog and the import graph (`ftfof dvc-yaml`): each stage's
command, the artefacts it reads and writes (:mod:`ftfof.pipeline.catalog`), the params it reads
(:data:`STAGES`, the one hand-kept list) and every project file its command imports
(:mod:`ftfof.pipeline.imports`). Nothing else is listed by hand, so a new import can never be
missed: a stage is stale exactly when code it runs changed."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from ftfof.pipeline.catalog import ARTEFACTS, tracked
from ftfof.pipeline.catalog import STAGES as READS_WRITES
from ftfof.pipeline.imports import ROOT, command_modules, imported_files

# what most stages share: the robot on its surface, on the platform's bench and solver
_ROBOT = ("base.seed", "robot", "robots.${robot}", "surface", "surfaces.${surface}", "platform")
_SOLVER = ("feasibility", "acquire.leg_model", "acquire.solver")
_BENCH = (*_ROBOT, *_SOLVER, "baselines")
_SEARCH = (*_ROBOT, *_SOLVER, "base.search_seed", "optimize")
_SLIP = ("climb", "evaluate.slip_scenario", "evaluate.slip_comparison")


@dataclass(frozen=True)
class Stage:
    command: str  # the `ftfof` sub-command (the catalog's writer of the stage's artefacts)
    params: tuple[str, ...]  # the params.yaml keys it reads
    flags: str = ""  # arguments the pipeline passes


STAGES: dict[str, Stage] = {
    "sample": Stage("sample", ("base.seed", "robot", "robots.${robot}", "feasibility", "sample")),
    "acquire": Stage("acquire", (*_BENCH, "acquire.max_failure_rate", "acquire.baselines")),
    "dataset": Stage("dataset", ("base.seed", "robot", "robots.${robot}.timing", "dataset")),
    "train": Stage("train", ("base.seed", "base.search_seed", "train")),
    "optimize": Stage("optimize", (*_SEARCH, "sample", "train.use", "train.alias")),
    "refine": Stage(
        "refine", (*_SEARCH, "sample", "dataset", "train", "refine", "acquire.max_failure_rate")
    ),
    "polish": Stage("polish", (*_SEARCH, "dataset", "polish")),
    # the robot's stages: the climbs, the controllers under slip, the ε study
    "climb": Stage("climb-table", (*_BENCH, "surfaces", "climb", "evaluate.climb")),
    "slip": Stage("slip", (*_BENCH, "surfaces.${evaluate.slip_scenario.surface}", *_SLIP)),
    "study": Stage("study eps", (*_BENCH, "study.eps")),
    "evaluate": Stage(
        "evaluate", (*_BENCH, "acquire.max_failure_rate", "train.alias", "evaluate", "climb.steps")
    ),
    "identify": Stage(
        "identify", (*_ROBOT[:4], "surfaces", "platform", "acquire", "identify"), "--if-enabled"
    ),
}

# files a module reads at run time beside its imports
RESOURCES = {"ftfof/report/html.py": ("ftfof/report/templates",)}
PERSIST = {"acquisition", "refine", "polish", "evaluate", "climbs_table"}  # resumable jobs
UNCACHED = {"acquire_timing", "optimize_convergence", "identify_outputs"}  # small, for the user
HEADER = (
    "# Written by `ftfof dvc-yaml` from ftfof/pipeline/catalog.py (artefacts),\n"
    "# ftfof/pipeline/dvcfile.py (params) and the import graph (code): edit those, not this.\n"
)


def render() -> str:
    """dvc.yaml's text."""
    stages = {name: _stage(name, stage) for name, stage in STAGES.items()}
    return HEADER + yaml.safe_dump({"stages": stages}, sort_keys=False, width=100)


def _stage(name: str, stage: Stage) -> dict[str, Any]:
    reads, writes = READS_WRITES[name]
    entry: dict[str, Any] = {
        "cmd": f"python -m ftfof {stage.command} {stage.flags}".rstrip(),
        "deps": [*dict.fromkeys(str(tracked(a)) for a in reads), *code_deps(stage.command)],
        "params": list(stage.params),
    }
    for artefact in writes:
        if ARTEFACTS[artefact].part_of is None:
            section, options = _kind(artefact)
            path = str(ARTEFACTS[artefact].path)
            entry.setdefault(section, []).append({path: options} if options else path)
    return entry


def _kind(name: str) -> tuple[str, dict[str, bool] | None]:
    """Where an artefact goes in its stage (outs, metrics, plots) and how DVC keeps it."""
    if name.endswith("_summary"):
        return "metrics", {"cache": False}  # the short summary `dvc exp show` compares
    if ARTEFACTS[name].format == "png":
        return "plots", {"cache": False}
    if name in PERSIST:
        return "outs", {"persist": True}  # an interrupted run resumes from its parts
    if name in UNCACHED or ARTEFACTS[name].path.suffix == ".json":  # committed to git
        return "outs", {"cache": False}
    return "outs", None


def code_deps(command: str) -> list[str]:
    """The project files ``command`` imports, and what they read, each directory whose every
    source file it imports listed as the directory."""
    module = command_modules()[command.split()[0]]
    files = {p.relative_to(ROOT).as_posix() for p in imported_files(module)}
    resources = [r for f in sorted(files) for r in RESOURCES.get(f, ())]
    return [*_folded(files), *resources]


def _folded(files: set[str]) -> list[str]:
    """``files`` with every directory they cover whole (all of its .py files, and nothing but
    them) named once instead."""
    out: list[str] = []
    for top in ("ftfof", "stages"):
        out.extend(_fold(ROOT / top, files))
    return out


def _fold(directory: Path, files: set[str]) -> list[str]:
    inside = [p for p in sorted(directory.iterdir()) if p.name != "__pycache__"]
    sources = [p for p in directory.rglob("*.py") if "__pycache__" not in p.parts]
    others = [p for p in directory.rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    rel = directory.relative_to(ROOT).as_posix()
    if sources and all(p.relative_to(ROOT).as_posix() in files for p in others):
        return [rel]
    out = [p.relative_to(ROOT).as_posix() for p in inside if p.is_file()]
    out = [f for f in out if f in files]
    for sub in inside:
        if sub.is_dir():
            out.extend(_fold(sub, files))
    return out
