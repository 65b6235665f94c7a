"""Did a refactor change a run? Two paper-scale runs side by side: ``reports/metrics.json`` figure
for figure (timings aside), and every climb's channels, bit for bit.

    python bench/same_run.py OLD NEW

OLD and NEW are run roots (a clone after `dvc repro`, or a copy of its reports/ and data/). The
climbs are looked for where each layout keeps them: ``data/climb`` and ``data/slip_comparison``
(the climb and slip stages), else ``data/evaluate/climb`` and its ``slip/`` (when evaluate ran
them). Exits 1 on any difference, naming it.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pyarrow.parquet as pq

TIMING = re.compile(r"seconds|wall|elapsed|duration", re.I)  # what a machine's speed changes


def leaves(node: Any, at: str = "") -> Iterator[tuple[str, Any]]:
    """Every (dotted path, value) of a JSON tree but the timings."""
    if isinstance(node, dict):
        for key, value in node.items():
            if not TIMING.search(str(key)):
                yield from leaves(value, f"{at}.{key}" if at else str(key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from leaves(value, f"{at}[{i}]")
    else:
        yield at, node


def same(x: Any, y: Any) -> bool:
    return x == y or (
        isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y)
    )


def metrics_differences(old: Path, new: Path) -> list[str]:
    a, b = (dict(leaves(json.loads((r / "reports/metrics.json").read_text()))) for r in (old, new))
    keys = sorted(a.keys() | b.keys())
    return [
        f"metrics {k}: {a.get(k)!r} -> {b.get(k)!r}" for k in keys if not same(a.get(k), b.get(k))
    ]


def climbs(root: Path) -> dict[str, Path]:
    """Each climb's channel file by name, in either layout."""
    places = [root / "data/climb", root / "data/slip_comparison"]
    if not places[0].exists():
        places = [root / "data/evaluate/climb", root / "data/evaluate/climb/slip"]
    return {p.name: p for place in places for p in sorted(place.glob("*.parquet"))}


def climb_differences(old: Path, new: Path) -> tuple[int, list[str]]:
    a, b = climbs(old), climbs(new)
    out = [f"climb {n}: only in {'OLD' if n in a else 'NEW'}" for n in sorted(a.keys() ^ b.keys())]
    for name in sorted(a.keys() & b.keys()):
        if not pq.read_table(a[name]).equals(pq.read_table(b[name])):
            out.append(f"climb {name}: channels differ")
    return len(a.keys() & b.keys()), out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    args = parser.parse_args()
    differences = metrics_differences(args.old, args.new)
    compared, climb_lines = climb_differences(args.old, args.new)
    differences += climb_lines
    figures = sum(1 for _ in leaves(json.loads((args.new / "reports/metrics.json").read_text())))
    print(f"{figures} figures of metrics.json and {compared} climbs' channels compared")
    print("\n".join(differences) if differences else "identical (timings aside)")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
