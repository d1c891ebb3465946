"""Columns of a metadata table as numpy arrays, whatever a broken file holds: what the
checks read of ``people.parquet`` and ``cameras.parquet``. A column missing, of another
kind or width, or a row without its key raises one ``PhavUserError`` naming the file and
the column; a null value or row of numbers reads as NaN, in its own row."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from phav_spec.errors import PhavUserError

if TYPE_CHECKING:
    import pyarrow as pa


def column(table: pa.Table, name: str, source: str) -> pa.Array:
    """Column ``name`` of ``table`` (read from ``source``) as one array."""
    if name not in table.column_names:
        raise PhavUserError("no such column", source=source, field=name)
    return table.column(name).combine_chunks()


def keys(table: pa.Table, name: str, source: str) -> np.ndarray:
    """A key column (a video id, a role) as Python values, every row holding one."""
    array = column(table, name, source)
    if array.null_count:
        raise PhavUserError(f"{array.null_count} rows without a value", source=source, field=name)
    return np.asarray(array.to_pylist(), dtype=object)


def numbers(table: pa.Table, name: str, source: str, *, key: bool = False) -> np.ndarray:
    """A numeric column as floats, a null as NaN; a ``key`` (a frame, a person id) in every row."""
    values = _floats(column(table, name, source), name, source)
    if key and not np.isfinite(values).all():
        raise PhavUserError(f"{int((~np.isfinite(values)).sum())} rows without a number", source=source, field=name)
    return values


def fixed_lists(table: pa.Table, name: str, width: int, source: str) -> np.ndarray:
    """A list<float64>[width] column as (rows, width) floats: a null row, or a null value in
    one, as NaN, every row where it is."""
    import pyarrow as pa
    import pyarrow.compute as pc

    array = column(table, name, source)
    kind = array.type
    out = np.full((len(array), width), np.nan)
    if pa.types.is_null(kind):  # no rows, or only nulls
        return out
    if not (pa.types.is_list(kind) or pa.types.is_large_list(kind) or pa.types.is_fixed_size_list(kind)):
        raise PhavUserError(f"{kind}, not a list of {width} numbers", source=source, field=name)
    null = array.is_null().to_numpy(zero_copy_only=False)
    lengths = pc.list_value_length(array).to_numpy(zero_copy_only=False)[~null]
    if (lengths != width).any():
        raise PhavUserError(f"rows of {int(lengths[lengths != width][0])} values, not {width}", source=source,
                            field=name)  # fmt: skip
    if (~null).any():
        # flatten() leaves out null rows: their values go to the rows that are there.
        out[~null] = _floats(pc.list_flatten(array), name, source).reshape(-1, width)
    return out


def _floats(array: pa.Array, name: str, source: str) -> np.ndarray:
    """``array``'s values as floats (nulls as NaN), or an error where they are not numbers
    (text that reads as one too: the contract's columns are numeric)."""
    import pyarrow as pa

    kind = array.type
    if not (pa.types.is_integer(kind) or pa.types.is_floating(kind) or pa.types.is_null(kind)):
        raise PhavUserError(f"{kind}, not numbers", source=source, field=name)
    return np.asarray(array.to_numpy(zero_copy_only=False), dtype=float)
