"""Each stage's report as the metrics its MLflow run logs, in the one naming scheme of every
metric (:func:`metric_name`), without NaN or infinities (:func:`finite`); one builder per stage,
as :mod:`ftfof.report.stage_summaries` has one summariser per stage for DVC; and the settings a
run logs as params (:func:`run_settings`)."""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import Any

from ftfof.evaluate.table import climbs_of

_SCOPE = re.compile(r"^[a-z][a-z0-9_]*$")
_PART = re.compile(r"[^A-Za-z0-9_]+")


def metric_name(scope: str, *parts: object) -> str:
    """The one naming scheme of every MLflow metric: ``<scope>.<name>[.<detail>...]``, dotted,
    the scope a lowercase word (``time``, ``search``, ``optimum``, ``fidelity``, ``table``...),
    the rest as the project spells them (objectives ``fs1``, targets ``Fd``), other characters
    as ``_``. One scheme so that a metric is found by the same name in every stage's runs."""
    if not _SCOPE.match(scope):
        raise ValueError(f"metric scope {scope!r} is not a lowercase word")
    if not parts:
        raise ValueError(f"metric {scope!r} has no name after its scope")
    return ".".join([scope, *(_PART.sub("_", str(p)).strip("_") for p in parts)])


def flatten(data: Mapping[str, Any], prefix: str = "") -> dict[str, str]:
    """Nested settings as MLflow params: dotted keys, string values."""
    out: dict[str, str] = {}
    for key, value in data.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(flatten(value, f"{name}."))
        else:
            out[name] = str(value)
    return out


def run_settings(
    sections: Mapping[str, object], robot: str, surface: str, seed: int, search_seed: int
) -> dict[str, str]:
    """What a stage's run logs as MLflow params: its settings ``sections``, the robot and
    surface, and the seeds every random stream comes from (``base.seed``, and the search's)."""
    return flatten(
        {
            **sections,
            "robot": robot,
            "surface": surface,
            "base": {"seed": seed, "search_seed": search_seed},
        }
    )


def finite(metrics: Mapping[str, float]) -> dict[str, float]:
    """``metrics`` as floats without NaN and infinities (MLflow rejects them)."""
    return {k: float(v) for k, v in metrics.items() if math.isfinite(float(v))}


def train(summary: dict) -> dict[str, float]:
    """The train run's metrics: its time and each peak model's errors."""
    out = {metric_name("time", "seconds"): summary["wall_seconds"]}
    out.update(
        {
            metric_name("peak", target, model, k): v
            for target, entry in summary["peaks"].items()
            for model in ("gp", "gru")
            for k, v in entry[model].items()
        }
    )
    return finite(out)


def train_model(result: dict) -> dict[str, float]:
    """A model's validation metrics and best epoch (its child run of the train run)."""
    out = {
        metric_name("validation", t, k): v
        for t, m in result["metrics"].items()
        for k, v in m.items()
    }
    out[metric_name("train", "best_epoch")] = result["history"]["best_epoch"]
    return finite(out)


def optimize(summary: dict) -> dict[str, float]:
    """The optimize run's metrics: its time, the front, and the optimum as predicted."""
    name = metric_name
    return finite(
        {
            name("time", "seconds"): summary["seconds"],
            name("time", "ms_per_generation"): summary["ms_per_generation"],
            name("front", "size"): summary["front"]["size"],
            name("front", "rejected_by_recheck"): summary["front"]["rejected_by_recheck"],
            **{
                name("optimum", "predicted", k): v
                for k, v in summary["optimum"]["objectives"].items()
            },
        }
    )


def refine_round(record: dict[str, Any]) -> dict[str, float]:
    """A refinement round's numbers: ``refine.added``, ``time.seconds``,
    ``fidelity.<objective>.<stat>``, ``optimum.<predicted|simulated>.<objective>``."""
    name = metric_name
    out = {name("refine", "added"): record["added"], name("time", "seconds"): record["seconds"]}
    for objective, values in record["fidelity"].items():
        out.update({name("fidelity", objective, k): v for k, v in values.items()})
    for kind, values in record["optimum"].items():
        out.update({name("optimum", kind, n): v for n, v in values.items()})
    return finite(out)


def polish(report: dict[str, Any]) -> dict[str, float]:
    """``time.seconds``, and when it polished ``polish.simulated`` and
    ``optimum.simulated.<objective>``."""
    name = metric_name
    out = {name("time", "seconds"): report["seconds"]}
    if report["polished"]:
        out[name("polish", "simulated")] = report["simulated"]
        out.update(
            {name("optimum", "simulated", k): v for k, v in report["optimum"]["simulated"].items()}
        )
    return finite(out)


def evaluate(summary: dict) -> dict[str, float]:
    """``table.<row>.<column>`` (Table I analogue), ``fidelity.<objective>.<stat>`` and
    ``fidelity.<objective>.bound`` (the simulator's own rho), ``climb.<trajectory>.<figure>``
    (the climbing robot; ``fell`` as 0 or 1), ``slip.<controller>.<figure>``
    (evaluate.slip_comparison) and ``time.seconds``."""
    name = metric_name
    out = {
        name("table", row_name, key): value
        for row_name, row in summary["table"].items()
        for key, value in row.items()
        if isinstance(value, int | float)
    }
    for objective, values in summary["fidelity"].items():
        out.update({name("fidelity", objective, k): v for k, v in values.items()})
    for objective, values in (summary.get("fidelity_bound") or {}).items():
        if values["spearman"] is not None:
            out[name("fidelity", objective, "bound")] = values["spearman"]
    for trajectory, climbed in climbs_of(summary.get("climb", {})).items():
        out.update(
            {
                name("climb", trajectory, k): float(v)
                for k, v in climbed.items()
                if isinstance(v, int | float) and v is not None
            }
        )
    for controller, row in summary.get("slip", {}).items():
        out.update({name("slip", controller, k): float(v) for k, v in row.items() if v is not None})
    out[name("time", "seconds")] = summary["seconds"]
    return finite(out)
