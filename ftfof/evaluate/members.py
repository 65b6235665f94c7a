"""The re-simulated optimum and front members judged by the robot's rules: what each trades, and
whether a real foot could run it (the film, the release, the landing, the hold, the shake)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd

from ftfof.data.faults import Faults, foot_faults
from ftfof.evaluate.film_check import FilmCheck
from ftfof.evaluate.runs import OPTIMUM, figures_of, run_name, simulated_rows
from ftfof.robot import RobotContext
from ftfof.rules import FootRules


def front_members(
    df: pd.DataFrame, T3: float, rules: FootRules, films: FilmCheck | None = None
) -> dict:
    """The re-simulated optimum and front members side by side: what each trades (pull, jitter,
    landing press), whether its film survives, its pad lets go and clears the wall, it lands
    pressing within the robot's tolerance of a and the body shakes within the robot's limit
    (``rules``, the simulator check's, with where the film limit comes from), so the
    choice can be judged in simulation. With ``films``, each member's bend on the check film
    too, and whether it keeps fc there."""
    members = [
        _member(row, T3, rules, films) for _, row in simulated_rows(df).iterrows()
    ]  # a few tens of rows, once per evaluation

    def fraction(key: str) -> float | None:
        """Over every member; one without a verdict (no run on the check film) counts as not
        verified."""
        return round(float(np.mean([bool(m[key]) for m in members])), 4) if members else None

    return {
        "members": members,
        "film_safe_fraction": fraction("film_safe"),
        "film_safe_on_check_film_fraction": fraction("film_safe_on_check_film")
        if films is not None
        else None,
        "lets_go_fraction": fraction("lets_go"),
        "lands_fraction": fraction("lands"),
        "holds_fraction": fraction("holds"),
        "calm_fraction": fraction("calm"),
        "clean_fraction": fraction("clean"),
        "film_limit": rules.film.as_dict(),
        "swing_clearance": rules.swing_clearance,
        "landing_tolerance": rules.landing_tolerance,
        "body_acc_limit": rules.body_acc_limit,
        "proof_pull": rules.proof_pull,
    }


def _member(row: pd.Series, T3: float, rules: FootRules, films: FilmCheck | None) -> dict:
    """One re-simulated run's figures and verdicts under ``rules`` (:func:`front_members`)."""
    f = figures_of(row, T3)
    faults = run_faults(row, f, rules)
    return {
        "row": int(row.sample_id),
        "optimum": row.source == OPTIMUM,
        "peak_pull": round(f["peak_pull"], 4),
        "jitter": round(f["jitter"], 4),
        "landing_pre_pressure_error": round(abs(f["landing_pre_pressure"] - rules.pre_pressure), 4),
        "min_bend_radius": round(f["min_bend_radius"], 6),
        "film_safe": not faults.film,
        **_on_check_film(films, run_name(row.source, int(row.sample_id)), rules.film.fc),
        "max_clearance": round(float(row.max_clearance), 6),
        "lets_go": not faults.release,
        "release_fault": faults.release,
        "lands": not faults.landing,
        "landing_fault": faults.landing,
        "held_pull": rounded(f["held_pull"]),
        "holds": not faults.hold,
        "hold_fault": faults.hold,
        "calm": not faults.shake,
        "shake_fault": faults.shake,
        "clean": faults.clean,  # a real foot could run it
    }


def rounded(value: float) -> float | None:
    """``value`` to four decimals, or None where the run did not measure it (JSON has no NaN)."""
    return round(value, 4) if np.isfinite(value) else None


def run_faults(row: pd.Series, figures: dict[str, float], rules: FootRules) -> Faults:
    """What in one simulated run (an acquisition row, its ``figures``) a real foot could not
    run: the film, the release, the landing, the proof pull's hold and the body's shake under
    ``rules``."""
    return foot_faults(
        np.asarray(row.t, dtype=float),
        np.asarray(row.bonds, dtype=float),
        np.asarray(row.Fp, dtype=float),
        {
            **figures,
            "switch_time": float(row.switch_time),
            "max_clearance": float(row.max_clearance),
            "proof_held": float(row.get("proof_held", np.nan)),
        },
        rules,
    )


def _on_check_film(films: FilmCheck | None, name: str, fc: float) -> dict[str, Any]:
    """A member's bend on the check film and whether it keeps fc there (None: no such run)."""
    if films is None:
        return {}
    pair = films.pair(name)
    return {
        "min_bend_radius_on_check_film": None if pair is None else round(pair[1], 6),
        "film_safe_on_check_film": None if pair is None else pair[1] >= fc,
    }


def judged_front(ctx: RobotContext, df: pd.DataFrame, films: FilmCheck | None = None) -> dict:
    """:func:`front_members` with the robot's rules."""
    return front_members(df, ctx.policy.timing.T3, ctx.rules, films)
