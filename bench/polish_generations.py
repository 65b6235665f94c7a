"""How many generations does polish need? A finished run's polish cut at G generations: the
search is replayed from its journal (the same seed asks the same batches, so nothing of it is
simulated again), then its front is confirmed with fresh copies and RHS chooses, as the stage
does. Prints, per G, the chosen trajectory's confirmed means, and how many trajectories the
search simulated up to G (the stage's cost grows with them) (docs/decisions/0046).

Run it in a checkout whose `dvc repro` has finished: it reads ``data/refine`` and
``data/polish/journal.jsonl``, and writes only under a temporary directory.

Run: python bench/polish_generations.py [G,G,...]   (default 10,14,20 and the params')
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from stages.runtime import pin_numerics

pin_numerics()  # the journal's batches are keyed by their bytes: the stage's numerics

from ftfof.config import Params  # noqa: E402
from ftfof.optimize.select import Verdict  # noqa: E402
from ftfof.pipeline import polish as stage  # noqa: E402
from ftfof.pipeline.artefacts import POLISH_READS, read_optimum  # noqa: E402
from ftfof.pipeline.bench import context_of  # noqa: E402
from ftfof.pipeline.catalog import path  # noqa: E402
from ftfof.pipeline.params_file import load_params  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def cut_at(params: Params, generations: int, scratch: Path) -> dict[str, Any]:
    """The polish report of the run cut at ``generations``, its journal a copy of the run's."""
    params = params.model_copy(
        update={"polish": params.polish.model_copy(update={"generations": generations})}
    )
    out = scratch / f"g{generations}"
    out.mkdir()
    shutil.copy(path("polish") / stage.JOURNAL, out / stage.JOURNAL)
    ctx = context_of(params)
    inputs = read_optimum(path("refine_optimize"), ctx.name, POLISH_READS)
    passed = [Verdict(**v) for v in inputs.optimum["simulator_check"] if v["ok"]]
    paths = stage.Paths(path("refine_optimize"), path("refine_models"), out, out / "polish.json")
    return stage._polish(params, ctx, inputs, passed, paths)


def main(cuts: list[int]) -> None:
    os.chdir(ROOT)  # the params and the run's artefacts are where the pipeline keeps them
    params = load_params(Path("params.yaml"))
    print(f"{'G':>3} {'simulated':>9} {'row':>4} {'fs1 N':>7} {'fsj m/s2':>8}  the others")
    with tempfile.TemporaryDirectory() as scratch:
        for g in sorted({*cuts, params.polish.generations}):
            report = cut_at(params, g, Path(scratch))
            if not report["polished"]:
                print(f"{g:>3} {report.get('simulated', 0):>9} not polished: {report['reason']}")
                continue
            chosen = report["optimum"]["simulated"]
            rest = ", ".join(f"{k} {v:.4g}" for k, v in chosen.items() if k not in ("fs1", "fsj"))
            print(f"{g:>3} {report['simulated']:>9} {report['optimum']['row']:>4} "
                  f"{chosen['fs1']:7.3f} {chosen['fsj']:8.3f}  {rest}")  # fmt: skip


if __name__ == "__main__":
    cuts = [int(g) for g in sys.argv[1].split(",")] if len(sys.argv) > 1 else [10, 14, 20]
    if min(cuts) < 1:
        sys.exit("polish_generations: every G must be at least 1 (0 is no polish at all)")
    main(cuts)
