"""Output formats of the optimiser's choice, on synthetic records."""

from __future__ import annotations

from ftfof.optimize.select import convergence_csv


def test_convergence_csv_has_one_line_per_record():
    records = [
        {"generation": 1, "evaluations": 24, "feasible": 3, "front": 2, "hypervolume": 0.123456789},
        {"generation": 5, "evaluations": 120, "feasible": 24, "front": 9, "hypervolume": 0.5},
    ]
    assert convergence_csv(records) == (
        "generation,evaluations,feasible,front,hypervolume\n1,24,3,2,0.12345679\n5,120,24,9,0.5\n"
    )
