"""Reading an `mtwin dataset` folder with pyarrow."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional, Sequence, Union

import pyarrow as pa
import pyarrow.dataset as ds

from .layout import manifest_tables

PathLike = Union[str, os.PathLike]

#: The Hive partition columns of every table (``machine=…/split=…/shard=I``). Typed here
#: rather than inferred: a machine named ``5`` stays a string, a shard is always an integer.
PARTITIONING = ds.partitioning(
    pa.schema([("machine", pa.string()), ("split", pa.string()), ("shard", pa.int32())]),
    flavor="hive",
)


def dataset(out: PathLike, table: str) -> ds.Dataset:
    """``out/<table>`` as one Hive-partitioned pyarrow dataset (lazy; for filters, scanners)."""
    path = Path(out) / table
    if not path.is_dir():
        raise FileNotFoundError(f"no table {table!r}: {path} is not a folder")
    return ds.dataset(path, format="parquet", partitioning=PARTITIONING)


def read(
    out: PathLike,
    table: str,
    *,
    columns: Optional[Sequence[str]] = None,
    filter: Optional[ds.Expression] = None,
    sort: bool = True,
) -> pa.Table:
    """Table ``table`` of the dataset in ``out`` (``cases``, ``volumetric``, …) as a pyarrow
    Table, with the partition columns ``machine``, ``split`` (strings) and ``shard`` (int32).

    With ``sort`` (the default) the rows are in ``case_id`` order, and a case's rows in the
    order the file has them (a stable sort), so two datasets made alike read equal.
    ``columns`` and ``filter`` go to :meth:`pyarrow.dataset.Dataset.to_table`, e.g.
    ``filter=pyarrow.dataset.field("split") == "train"``.
    """
    data = dataset(out, table)
    if columns is not None and sort and "case_id" not in columns:
        result = data.to_table(columns=[*columns, "case_id"], filter=filter)
        return result.take(_case_order(result)).drop_columns(["case_id"])
    result = data.to_table(columns=list(columns) if columns is not None else None, filter=filter)
    if sort and "case_id" in result.column_names:
        result = result.take(_case_order(result))
    return result


def _case_order(table: pa.Table) -> pa.Array:
    import pyarrow.compute as pc

    # sort_indices is stable: rows of one case keep their order in the file.
    return pc.sort_indices(table, sort_keys=[("case_id", "ascending")])


def tables(out: PathLike) -> list:
    """The tables of the dataset in ``out``, from its manifest (``["cases", "volumetric"]``)."""
    return manifest_tables(out)
