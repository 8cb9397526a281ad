"""Join the sampled parameters of each case with its measurement table.

    python examples/join_cases.py DIR [TABLE] [--columns dx_um dy_um dz_um] [--params 4]

Prints, per case, the RMS of the deviation columns of TABLE (default ``volumetric``; by default
every double column named ``d…_um``, e.g. dx_um, dy_um, dz_um: the RMS of the length of
the deviation vector over the case's points) next to the case's split and first sampled
parameters. Uses pyarrow only: ``Table.group_by`` for the per-case sums, ``Table.join`` on
``case_id`` for the parameters.
"""

from __future__ import annotations

import argparse
import functools
import math
import sys

import pyarrow as pa
import pyarrow.compute as pc

import mtwin_ray

PARTITIONS = ("machine", "split", "shard")


def deviation_columns(table: pa.Table) -> list:
    return [
        n
        for n in table.column_names
        if n.startswith("d")
        and n.endswith("_um")
        and pa.types.is_floating(table.schema.field(n).type)
    ]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", metavar="DIR", help="dataset folder (mtwin dataset --out)")
    parser.add_argument("table", nargs="?", default="volumetric", help="measurement table")
    parser.add_argument("--columns", nargs="+", help="deviation columns (default: d…_um)")
    parser.add_argument("--params", type=int, default=4, help="sampled parameters to print")
    args = parser.parse_args()

    cases = mtwin_ray.read(args.out, "cases")
    measured = mtwin_ray.read(args.out, args.table)
    columns = args.columns or deviation_columns(measured)
    if not columns:
        sys.exit(f"no deviation column in {args.table}: pass --columns")

    # Squared length of the deviation vector per row, then its mean per case.
    squared = functools.reduce(pc.add, [pc.multiply(measured[c], measured[c]) for c in columns])
    per_row = pa.table({"case_id": measured["case_id"], "sq": squared})
    per_case = per_row.group_by("case_id").aggregate([("sq", "mean"), ("sq", "count")])

    params = [n for n in cases.column_names if n not in ("case_id", "case_seed", *PARTITIONS)]
    shown = params[: args.params]
    joined = per_case.join(
        cases.select(["case_id", "split", *shown]), keys="case_id", join_type="inner"
    ).sort_by("case_id")

    unit = columns[0].rsplit("_", 1)[-1]
    width = {p: max(len(p), 10) for p in shown}
    print(
        f"{'case':>5} {'split':<5} {'points':>6} {'rms_' + unit:>9}  "
        + "  ".join(f"{p:>{width[p]}}" for p in shown)
    )
    for row in joined.to_pylist():
        values = "  ".join(f"{row[p]:>{width[p]}.4g}" for p in shown)
        rms = math.sqrt(row["sq_mean"])
        print(f"{row['case_id']:>5} {row['split']:<5} {row['sq_count']:>6} {rms:>9.3f}  {values}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
