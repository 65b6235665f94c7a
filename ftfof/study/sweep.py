"""A sweep of the pipeline's presets and seeds: the product of a few named settings, each one
named experiment, and the table it is read by.

``robots=mst_m3f,mst_q surfaces=acrylic,glass`` is four experiments, named ``mst_m3f-acrylic``
and so on; ``seeds=1,2,3`` re-runs the chain from train on with three search seeds on the same
data (the robustness of the answer). Each experiment sets every axis explicitly, and registers
its surrogates under its own alias (:attr:`Experiment.alias`): the registry is shared, and an
experiment that moved ``champion`` made the workspace's next run refuse its own models. Queuing
them as DVC experiments is :mod:`ftfof.pipeline.sweep`; the queue's arguments and the reading of
its status are here (:func:`queue_args`, :func:`unfinished`, :func:`failed`).
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from ftfof.errors import ParamsError

# command-line axis -> params key
AXES = {"robots": "robot", "surfaces": "surface", "seeds": "base.search_seed"}
_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")


@dataclass(frozen=True)
class Experiment:
    name: str
    settings: dict[str, str]  # params key -> value

    @property
    def alias(self) -> str:
        """The registry alias of this experiment's surrogates (a valid ``train.alias``)."""
        return "exp-" + re.sub(r"[^A-Za-z0-9_-]", "-", self.name)

    @property
    def params(self) -> dict[str, str]:
        """Every params key this experiment sets: its axes and its alias."""
        return {**self.settings, "train.alias": self.alias}


def parse_axes(tokens: Sequence[str]) -> dict[str, list[str]]:
    """``["robots=a,b", "surfaces=c"]`` -> ``{"robot": ["a", "b"], "surface": ["c"]}``."""
    axes: dict[str, list[str]] = {}
    for token in tokens:
        axis, sep, values = token.partition("=")
        if not sep or axis not in AXES:
            raise ParamsError(f"sweep {token}", f"expected one of {', '.join(AXES)}=NAME[,NAME...]")
        names = [v.strip() for v in values.split(",")]
        if not all(names) or len(set(names)) != len(names):
            raise ParamsError(f"sweep {token}", "names must be non-empty and distinct")
        if bad := [n for n in names if not _NAME.match(n)]:
            raise ParamsError(f"sweep {token}", f"not a usable experiment name part: {bad[0]!r}")
        if axis == "seeds" and not all(n.isdigit() for n in names):
            raise ParamsError(f"sweep {token}", "seeds must be non-negative integers")
        if AXES[axis] in axes:
            raise ParamsError(f"sweep {token}", f"{axis} given twice")
        axes[AXES[axis]] = names
    if not axes:
        raise ParamsError("sweep", f"nothing to sweep: give {' and/or '.join(AXES)}")
    return axes


def check_presets(axes: Mapping[str, Sequence[str]], presets: Mapping[str, Sequence[str]]) -> None:
    """Every swept name must be a preset of params.yaml (``presets``: params key -> names); axes
    that are not presets (seeds) are not checked here."""
    for key, names in axes.items():
        if key not in presets:
            continue
        have = presets[key]
        if unknown := [n for n in names if n not in have]:
            raise ParamsError(
                f"sweep {key}", f"no {key} preset {unknown[0]!r} (have {', '.join(have)})"
            )


def plan(axes: Mapping[str, Sequence[str]], prefix: str = "") -> list[Experiment]:
    """The product of the axes, in the order given, one named experiment each."""
    keys = list(axes)

    def label(key: str, value: str) -> str:
        return f"seed{value}" if key == AXES["seeds"] else value

    return [
        Experiment(
            prefix + "-".join(label(k, v) for k, v in zip(keys, values, strict=True)),
            dict(zip(keys, values, strict=True)),
        )
        for values in itertools.product(*(axes[k] for k in keys))
    ]


def queue_args(experiment: Experiment) -> list[str]:
    """Arguments of ``dvc`` that queue ``experiment``."""
    sets = [arg for key, value in experiment.params.items() for arg in ("-S", f"{key}={value}")]
    return ["exp", "run", "--queue", "-n", experiment.name, *sets]


def unfinished(status_text: str, names: Sequence[str]) -> list[str]:
    """The experiments of ``names`` that ``dvc queue status`` still shows queued or running."""
    pending = []
    for line in status_text.splitlines():
        words = line.split()
        if any(name in words for name in names) and {"Queued", "Running"} & set(words):
            pending.append(next(n for n in names if n in words))
    return pending


def failed(status_text: str, names: Sequence[str]) -> list[str]:
    """The experiments of ``names`` that ``dvc queue status`` shows as failed."""
    return [
        n
        for line in status_text.splitlines()
        if "Failed" in line.split()
        for n in names
        if n in line.split()
    ]


# the columns a sweep is read by: what ran, and the optimum's figures against the reference
KEY_PARAMS = {  # the column -> its params key path; a null value (a search seed that follows the
    # seed) is shown as "-". The search seed is what ``seeds=`` varies
    "robot": ("robot",),
    "surface": ("surface",),
    "seed": ("base", "seed"),
    "search seed": ("base", "search_seed"),
}
KEY_METRICS = {  # the summary's name -> the column's
    "peak_pull": "pull [N]",
    "jitter": "detachment jitter [m/s²]",
    "landing_pre_pressure": "landing [N]",
    "min_bend_radius": "film radius [m]",
}


def key_columns(shown: list[dict], names: Sequence[str], summary: str) -> str:
    """A Markdown table of the experiments ``names`` from `dvc exp show --json` output: robot,
    surface, seed and search seed, the reference, and the optimum's pull, detachment jitter,
    landing press and film radius with their change against the reference, read from evaluate's
    DVC summary at ``summary`` (the full table has hundreds of columns: `dvc exp show`)."""
    found: dict[str, dict] = {}

    def walk(node: object) -> None:
        if isinstance(node, dict):
            if node.get("name") in names and isinstance(node.get("data"), dict):
                found[node["name"]] = node["data"]
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(shown)
    header = ["experiment", *KEY_PARAMS, "reference", *KEY_METRICS.values()]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for name in names:
        data = found.get(name, {})
        params = data.get("params", {}).get("params.yaml", {}).get("data", {})
        metrics = data.get("metrics", {}).get(summary, {}).get("data", {})
        optimum = metrics.get("optimum", {})
        cells = [name]
        for path in KEY_PARAMS.values():
            value: object = params
            for key in path:
                value = value.get(key, "?") if isinstance(value, dict) else "?"
            cells.append("-" if value is None else str(value))
        cells.append(str(metrics.get("reference", "?")))
        for metric in KEY_METRICS:
            value, change = optimum.get(metric), optimum.get(f"{metric}_change")
            cells.append("?" if value is None else f"{value:g} ({change:+.1f} %)")
        lines.append("| " + " | ".join(cells) + " |")
    note = "The optimum's figures, each with its change against the reference.\n\n"
    return note + "\n".join(lines) + "\n"
