"""How the simulated choice depends on RHS's alpha0 and on how many candidates are simulated,
across runs that differ only in their seed (docs/optimum.md).

Every recheck-passing member of each run's final front, its nominees left out
(``data/refine/optimize/front.parquet`` at a git revision: a commit or a ``dvc exp`` ref, read
through the DVC cache) is simulated once with the pipeline's simulator check; then, for each
alpha0 and candidate count, the choice ``optimize`` would make without refinement's nominees
(RHS on the predictions ranks the candidates, RHS on the simulated objectives of those that pass
chooses) is printed with its first three simulated objectives (MST-M3F: pull, jitter, landing
error), and the spread of the first two across the runs (range over mean).

Run: python bench/rhs_choice.py REV [REV ...]   (e.g. HEAD and the refs of `dvc exp list`)
"""

from __future__ import annotations

import io
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ftfof.optimize.select import FRONT as FRONT_ORIGIN
from ftfof.optimize.select import Verdict, verified_rhs
from ftfof.pipeline import catalog
from ftfof.pipeline.artefacts import FRONT_FILE
from ftfof.pipeline.bench import context_of
from ftfof.pipeline.params_file import load_params
from ftfof.pipeline.simcheck import simulator_check_of
from ftfof.trajectory.bezier import DECISION_NAMES

FRONT = (catalog.path("refine_optimize") / FRONT_FILE).as_posix()
ALPHAS = (0.9, 0.7, 0.5, 0.4)
CANDIDATES = (8, 16, 32)


def front_at(root: Path, rev: str) -> pd.DataFrame:
    import dvc.api

    with dvc.api.open(FRONT, repo=str(root), rev=rev, mode="rb") as f:
        return pd.read_parquet(io.BytesIO(f.read()))


def main(revs: list[str]) -> None:
    root = Path(__file__).resolve().parents[1]
    params = load_params(root / "params.yaml")
    ctx = context_of(params)
    check = simulator_check_of(params, ctx)
    names = list(ctx.robot.objectives)
    runs = []
    for rev in revs:
        front = front_at(root, rev)
        members = front.recheck_feasible
        if "origin" in front:  # refinement's nominees are not members of the front
            members = members & (front.origin == FRONT_ORIGIN)
        rows = front.row[members].to_numpy()
        X = front[list(DECISION_NAMES)].to_numpy(float)
        verdicts = {v.row: v for v in check(list(rows), X[rows])}
        ok = sum(v.ok for v in verdicts.values())
        print(f"{rev}: {len(rows)} front members simulated, {ok} pass the check", flush=True)
        runs.append((front[names].to_numpy(float), X, rows, verdicts))

    print(f"each run's choice as simulated {'/'.join(names[:3])}")

    def replay(verdicts: dict[int, Verdict]):
        return lambda asked, _: [verdicts[int(r)] for r in asked]

    for alpha in ALPHAS:
        for k in CANDIDATES:
            cfg = params.optimize.model_copy(update={"rhs_alpha": alpha})
            chosen = []
            for F, X, rows, verdicts in runs:
                index, *_ = verified_rhs(F, X, rows, cfg, replay(verdicts), k)
                chosen.append(verdicts[index].simulated)
            first = np.array(chosen)[:, :3]
            picks = "  ".join("/".join(f"{v:.2f}" for v in row) for row in first)
            spread = 100 * np.ptp(first[:, :2], axis=0) / first[:, :2].mean(axis=0)
            print(
                f"alpha0 {alpha:.1f}, {k:2d} candidates: {picks}  spread "
                f"{names[0]} {spread[0]:.0f} %, {names[1]} {spread[1]:.0f} %"
            )


if __name__ == "__main__":
    main(sys.argv[1:] or ["HEAD"])
