"""Explicit pyarrow schemas of the pipeline's tables, with units in the field metadata.

Readers validate against these schemas: a table missing a field, or holding one of another type,
is rejected with the field named, before any work is done.
"""

from __future__ import annotations

import pyarrow as pa

from ftfof.errors import DataError
from ftfof.trajectory.bezier import DECISION_NAMES


def field(name: str, dtype: pa.DataType, unit: str, doc: str) -> pa.Field:
    return pa.field(name, dtype, nullable=False, metadata={"unit": unit, "doc": doc})


TRAJECTORIES = pa.schema(
    [
        field("sample_id", pa.int64(), "", "row id, stable for a seed"),
        field("robot", pa.string(), "", "robot preset name"),
        *[field(n, pa.float64(), "m", f"control point coordinate {n}") for n in DECISION_NAMES],
        field("T1", pa.float64(), "s", "end of the detachment segment"),
        field("T2", pa.float64(), "s", "end of the swing segment"),
        field("T3", pa.float64(), "s", "end of the adhesion segment"),
        field("P15x", pa.float64(), "m", "landing point x"),
        field("P15z", pa.float64(), "m", "landing point z"),
    ]
)


def conform(table: pa.Table, schema: pa.Schema, source: str) -> pa.Table:
    """``table`` with ``schema``'s fields in order; names the first missing or mistyped field."""
    for f in schema:
        if f.name not in table.column_names:
            raise DataError(source, f"missing column {f.name!r} (expected {f.type})")
        got = table.schema.field(f.name).type
        if got != f.type:
            raise DataError(source, f"column {f.name!r} has type {got}, expected {f.type}")
        if table.column(f.name).null_count:
            raise DataError(source, f"column {f.name!r} has missing values")
    return table.select(schema.names).cast(schema)
