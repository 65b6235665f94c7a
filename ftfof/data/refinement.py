"""Rows a refinement round adds to the dataset: re-simulated front members.

They keep the train/validation split the dataset build gave them (``validation_fraction``, by the
split seed), so the held-out share joins the validation split that fine-tuning stops on. A
validation split of the original samples only never rewards learning the region the optimiser
went to: fine-tuning kept the previous weights all but unchanged (the round's own rows fitted at
correlation 0.72 before and after), and refinement did nothing. Their keys and source name the
round (``refine:<k>``).
"""

from __future__ import annotations

import pyarrow as pa

from ftfof.errors import DataError

PREFIX = "refine:"


def source(round_: int) -> str:
    """The dataset source of round ``round_``'s rows."""
    return f"{PREFIX}{round_}"


def from_rounds(sources: list[str]) -> list[bool]:
    """Which of these dataset sources are refinement rounds' rows (the optimiser's region)."""
    return [s.startswith(PREFIX) for s in sources]


def round_rows(built: pa.Table, round_: int) -> pa.Table:
    """Dataset rows (built from one round's simulations) relabelled as that round's rows.

    Keys become ``refine:<k>:<sample_id>``, unique across rounds because a round's sample ids are
    distinct front rows.
    """
    ids = built.column("sample_id").to_pylist()
    if len(set(ids)) != len(ids):
        raise DataError(source(round_), "re-simulated front rows must be distinct")
    name = source(round_)
    values = {
        "key": [f"{name}:{i}" for i in ids],
        "source": [name] * len(ids),
    }
    for column, new in values.items():
        index = built.schema.get_field_index(column)
        built = built.set_column(index, built.schema.field(index), pa.array(new, pa.string()))
    return built


def grow(table: pa.Table, rows: list[pa.Table]) -> pa.Table:
    """``table`` with ``rows`` appended (in order), its schema metadata kept; keys stay unique."""
    if not rows:
        return table
    grown = pa.concat_tables([table, *(r.cast(table.schema) for r in rows)])
    keys = grown.column("key").to_pylist()
    if len(set(keys)) != len(keys):
        raise DataError("refine", "a refinement row's key is already in the dataset")
    return grown.replace_schema_metadata(table.schema.metadata)
