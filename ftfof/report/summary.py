"""The report's first screen: the "run this" box (the chosen trajectory, its figures against the
reference and the published optimum, why RHS chose it, how to export it), Table I split so the
paper's columns come first, each cell coloured by its own sense of better, and a glossary."""

from __future__ import annotations

from typing import Any

from ftfof.evaluate.runs import PAPER_OPTIMUM, table_name
from ftfof.evaluate.table import COLUMNS, LANDED, TableRow
from ftfof.trajectory.bezier import DECISION_NAMES

# Table I's figures as the paper reports them: detachment force, pre-pressure, and the body's
# jitter where its IMU read it (during detachment)
PAPER = ("peak_detachment", "peak_pre_pressure", "jitter")
# how a column is better: lower (the default), higher, or closer to the pre-pressure a
SENSE = {
    "min_bend_radius": "higher",
    "landing_pre_pressure": "target",
    "rebond_fraction": "higher",
    "held_pull": "higher",
}
HEADLINE = {
    "peak_detachment": "the pull the pad's adhesion must bear to let go; lower leaves margin",
    "peak_pre_pressure": "the largest press on the wall; lower lands and presses more gently",
    "jitter": "the body's shake while the foot detaches (the paper's IMU figure); lower is calmer",
    "landing_pre_pressure": "the press the foot lands with; closest to a loads the pad as meant",
    "min_bend_radius": "the film's tightest bend; it must stay at or above fc, larger is safer",
    "held_pull": "the pull the landed pad held before a tenth let go; the stance must hold its"
    " robot's demand",
}
GLOSSARY = (
    ("fs1", "peak detachment force (FTFOF eq. 10)"),
    ("fs2", "mean detachment force until complete detachment (eq. 11)"),
    ("fs3", "distance of the landing pre-pressure from the optimal pre-pressure a (eq. 12)"),
    ("fs4", "mean height of the foot over the step (eq. 13)"),
    ("fs5", "path length of the adhesion segment, T2 to T3 (eq. 14)"),
    ("fs6", "bends sharper than 90° along the path: a rule, kept at 0 (eq. 15)"),
    ("fs7", "force jitter: the summed exceedances of the detachment force (eq. 16)"),
    ("fsj", "peak body acceleration during detachment: the IMU jitter of Table I"),
    ("fs1_normal, fs2_normal", "fs1 and fs2 on the normal part of the pull, as the paper's sensor"),
)


def better(key: str, value: float, reference: float, a: float) -> str:
    """'better', 'worse' or '' for ``value`` against ``reference`` in column ``key``."""
    sense = SENSE.get(key, "lower")
    if sense == "target":
        value, reference = abs(value - a), abs(reference - a)
    if value == reference or value != value or reference != reference:
        return ""
    if sense == "higher":
        return "better" if value > reference else "worse"
    return "better" if value < reference else "worse"


def _column(key: str) -> dict[str, Any]:
    label, unit = next((label, unit) for c, label, unit in COLUMNS + LANDED if c == key)
    scale = {"unit": "mm", "scale": 1e3} if unit == "m" else {"unit": unit, "scale": 1.0}
    return {"key": key, "label": label, "sense": SENSE.get(key, "lower"), **scale}


def tables(
    rows: list[TableRow], reference: str, a: float, breaks: dict[str, list[str]]
) -> list[dict[str, Any]]:
    """Table I in two tables, the paper's columns first, and a third for the landing where the
    robot has a proof pull, each cell with its change against the ``reference`` and its colour;
    ``a`` is the robot's optimal pre-pressure; each row says whether the robot can run it
    (``breaks``: the rules it breaks, where it was judged)."""
    ref = next(r for r in rows if r.trajectory == reference)
    landed = [c for c, _, _ in LANDED if c in ref.values]
    foot = [c for c in ref.values if c not in PAPER and c not in landed]
    out = []
    sections = (
        ("Table I: the paper's figures", PAPER),
        ("The foot and the film", foot),
        ("The landed pad: its re-bond and the proof pull it held", landed),
    )
    for title, keys in (s for s in sections if s[1]):
        columns = [_column(k) for k in keys]
        body = []
        for row in rows:
            cells = [
                {
                    "value": c["scale"] * row.values[c["key"]],
                    "change": row.change[c["key"]],
                    "class": better(c["key"], row.values[c["key"]], ref.values[c["key"]], a),
                }
                for c in columns
            ]
            broken = breaks.get(row.trajectory)
            runs = "–" if broken is None else ("yes" if not broken else f"no: {broken[0]}")
            body.append({"trajectory": row.trajectory, "cells": cells, "runs": runs})
        out.append({"title": title, "columns": columns, "rows": body, "feasibility": not out})
    return out


def run_this(
    rows: list[TableRow],
    reference: str,
    a: float,
    decision: dict[str, float],
    rhs: dict[str, Any],
    candidates: int,
) -> dict[str, Any]:
    """The chosen trajectory's box: its control points (mm), its headline figures against the
    ``reference`` and the published optimum, and why RHS chose it."""
    table = {r.trajectory: r for r in rows}
    optimum, ref = table["optimum"], table[reference]
    paper = table.get(table_name(PAPER_OPTIMUM))
    figures = []
    for key, meaning in HEADLINE.items():
        if key not in optimum.values:  # held_pull: only where the robot has a proof pull
            continue
        column = _column(key)
        value = optimum.values[key]
        known = paper is not None and paper.values[key] > 0
        vs_paper = 100.0 * (value / paper.values[key] - 1.0) if known else None
        figures.append(
            {
                **column,
                "value": column["scale"] * value,
                "vs_reference": optimum.change[key],
                "class": better(key, value, ref.values[key], a),
                "vs_paper": vs_paper,
                "paper_class": "" if paper is None else better(key, value, paper.values[key], a),
                "meaning": meaning,
            }
        )
    points = [
        {"point": name, "x": 1e3 * decision[f"{name}x"], "z": 1e3 * decision[f"{name}z"]}
        for name in dict.fromkeys(n[:-1] for n in DECISION_NAMES)
    ]
    return {"figures": figures, "points": points, "why": why(rhs, candidates)}


def why(rhs: dict[str, Any], candidates: int) -> str:
    """One sentence: how RHS narrowed the candidates the simulator measured down to one."""
    steps = rhs.get("steps", [])
    if not steps:
        return "It was the only candidate the simulator passed."
    visits = ", then ".join(f"{s['objective']} kept {len(s['remaining'])}" for s in steps)
    rule = (
        "; several were left and the lexicographic rule picked it" if rhs.get("tie_break") else ""
    )
    return (
        f"RHS visited the robot's objectives in priority order over the {candidates} "
        f"trajectories the simulator measured, keeping those within alpha = {rhs['alpha']:g} of "
        f"each one's best: {visits}{rule}."
    )
