"""Each stage's short summary for DVC: the few figures a reader compares across experiments.

`dvc exp show` and `dvc metrics diff` make a column of every number in every file a stage lists
under ``metrics:``; the stages' full reports (hundreds of numbers: per constraint, per target,
per baseline) made that table hundreds of columns wide. So each stage writes its full report as a
plain output, and beside it a summary of at most :data:`LIMIT` numbers (:data:`SUMMARIES`, one
summariser per stage) that dvc.yaml lists as its metrics. Each summariser reads the full report's
keys only, so a block added to a report (evaluate's, say) changes no summary until it is named
here.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from ftfof.evaluate.table import climbs_of

LIMIT = 20  # numbers per summary: about what a terminal row of `dvc exp show` holds per stage

Report = Mapping[str, Any]


def _keys(report: Report, *names: str) -> dict[str, Any]:
    """The top-level ``names`` that ``report`` has."""
    return {n: report[n] for n in names if n in report}


def sample(report: Report) -> dict[str, Any]:
    out = _keys(report, "samples", "draws", "acceptance_rate", "rejected_by_fine_recheck")
    return {**out, "rejected_by_kind": dict(report.get("rejected_by_kind", {}))} | _keys(
        report, "seconds"
    )


ACQUIRED = ("peak_detachment", "peak_pre_pressure", "peak_body_acc", "min_bend_radius")


def acquire(report: Report) -> dict[str, Any]:
    out = _keys(
        report,
        "samples",
        "ok",
        "failed",
        "failure_rate",
        "film_below_min_bend_radius",
        "seconds_per_sample",
        "wall_seconds",
    )
    out.update({f"{q}_mean": report[q]["mean"] for q in ACQUIRED if q in report})
    return out


def dataset(report: Report) -> dict[str, Any]:
    return _keys(
        report,
        "samples",
        "train",
        "validation",
        "baseline",
        "imported",
        "excluded_failed",
        "seq_len",
        "peak_detachment_mean",
        "seconds",
    )


TRAIN_TARGETS = ("pull", "jitter")  # fs1's and fsj's series: the paper's first two objectives


def train(report: Report) -> dict[str, Any]:
    """Per loss its best epoch, time and validation MSE of pull and jitter; per peak GP its rank
    correlation."""
    out: dict[str, Any] = _keys(report, "wall_seconds")
    for loss, entry in report.items():
        if isinstance(entry, Mapping) and "targets" in entry:
            out[loss] = {
                **_keys(entry, "best_epoch", "seconds"),
                **{
                    f"{t}_mse": entry["targets"][t]["mse"]
                    for t in TRAIN_TARGETS
                    if t in entry["targets"]
                },
            }
    peaks = report.get("peaks", {})
    out["peak_gp_spearman"] = {t: m["gp"]["spearman"] for t, m in peaks.items() if "gp" in m}
    return out


def optimize(report: Report) -> dict[str, Any]:
    out = _keys(
        report,
        "generations",
        "evaluations",
        "hypervolume",
        "feasible_in_final_population",
        "ms_per_generation",
        "seconds",
    )
    front = report.get("front", {})
    out["front"] = _keys(front, "size", "rejected_by_recheck")
    out["optimum"] = dict(report.get("optimum", {}).get("objectives", {}))
    return out


def refine(report: Report) -> dict[str, Any]:
    """The rounds run and points added, and the last round's fidelity and optimum on the first
    objective (what its stopping rule reads)."""
    rounds = report.get("rounds", [])
    out: dict[str, Any] = {
        "rounds": len(rounds),
        "added": sum(r["added"] for r in rounds),
        **_keys(report, "seconds"),
    }
    if rounds:
        last = rounds[-1]
        first = next(iter(last["fidelity"]))
        fidelity = last["fidelity"][first]
        out["last"] = {
            "objective": first,
            "spearman": fidelity["spearman"],
            "median_relative_error": fidelity["median_relative_error"],
            "predicted": last["optimum"]["predicted"][first],
            "simulated": last["optimum"]["simulated"][first],
        }
    return out


def polish(report: Report) -> dict[str, Any]:
    out = _keys(report, "polished", "reason", "simulated", "refused", "seconds")
    if "optimum" in report:
        out["optimum"] = dict(report["optimum"].get("simulated", {}))
    return out


EVALUATED = (  # Table I's figures of the optimum, each with its change against the reference
    "peak_detachment",
    "peak_pull",
    "peak_pre_pressure",
    "jitter",
    "landing_pre_pressure",
    "min_bend_radius",
)


def evaluate(report: Report) -> dict[str, Any]:
    """The reference, and the optimum's Table I figures with their changes against it (what
    `ftfof sweep` prints), its climb on the climbing robot, the model that produced it and the
    stage's time."""
    row = report.get("table", {}).get("optimum", {})
    optimum: dict[str, Any] = {}
    for name in EVALUATED:
        optimum.update(_keys(row, name, f"{name}_change"))
    climbed = _keys(report.get("climb", {}).get("optimum", {}), "jitter", "steps_done", "fell")
    if climbed:
        optimum["climb"] = climbed
    out = _keys(report, "reference", "optimum_origin", "optimum_front_row")
    return {**out, "optimum": optimum, **_keys(report, "seconds")}


def climb(report: Report) -> dict[str, Any]:
    """Per trajectory climbed, its steps done and its torque ratio (the hip servos' margin)."""
    return {n: _keys(r, "steps_done", "torque_ratio") for n, r in climbs_of(report).items()}


def slip(report: Report) -> dict[str, Any]:
    """Per controller, the slid foot's distance, whether the robot fell, and its estimator's
    median errors over the slips."""
    table = report.get("slip") or {}
    figures = ("slip_distance", "fell", "mu_error", "adhesion_error")
    return {c: _keys(row, *figures) for c, row in table.items()}


def study(report: Report) -> dict[str, Any]:
    """Per ε, the landing's pre-pressure and the detachment's body jitter."""
    return {
        f"eps_{p['eps']:g}": _keys(p, "landing_pre_pressure", "detachment_jitter")
        for p in report.get("points", [])
    }


def identify(report: Report) -> dict[str, Any]:
    """The surface and its estimates (Kalman and least squares), with the truth of a simulated
    log; only that it is off when it is."""
    out = _keys(report, "enabled", "surface", "source")
    for name in ("mu", "adhesion"):
        out.update({f"{name}_{k}": v for k, v in report.get(name, {}).items() if v is not None})
    return out


SUMMARIES: dict[str, Callable[[Report], dict[str, Any]]] = {
    "sample": sample,
    "acquire": acquire,
    "dataset": dataset,
    "train": train,
    "optimize": optimize,
    "refine": refine,
    "polish": polish,
    "climb": climb,
    "slip": slip,
    "study": study,
    "evaluate": evaluate,
    "identify": identify,
}


def numbers(data: object) -> int:
    """How many columns ``data`` makes in `dvc exp show`: its numeric leaves."""
    if isinstance(data, Mapping):
        return sum(numbers(v) for v in data.values())
    if isinstance(data, list):
        return sum(numbers(v) for v in data)
    return int(isinstance(data, int | float) and not isinstance(data, bool))
