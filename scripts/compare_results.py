#!/usr/bin/env python3
"""Checks that two `vitro batch` result directories hold the same results.

    python3 scripts/compare_results.py DIR_A DIR_B

Compares summary.parquet and (when there is one) series.parquet of both, sorted by run:
the same columns with the same types and the same values (NaN equal to NaN), leaving out
the wall-clock columns (`wall_s`, any column ending in `wall_s` or `wall_time_s`), which
differ from machine to machine. Used by CI to check that a Slurm job array's merged result
equals a one-process run of the same experiment. Exits 1 naming the first difference.
"""
import math
import sys
from pathlib import Path

import pyarrow.parquet as pq


def fail(msg):
    print(f"compare_results: {msg}", file=sys.stderr)
    sys.exit(1)


def wall(column):
    return column == "wall_s" or column.endswith("wall_s") or column.endswith("wall_time_s")


def same(a, b):
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return a == b


def load(directory, name):
    path = Path(directory) / name
    if not path.is_file():
        return None
    table = pq.read_table(path)
    keep = [c for c in table.column_names if not wall(c)]
    table = table.select(keep)
    order = sorted(range(table.num_rows), key=lambda i: table.column("run")[i].as_py())
    return table.take(order)


def compare(a_dir, b_dir, name):
    a, b = load(a_dir, name), load(b_dir, name)
    if a is None and b is None:
        return 0
    if a is None or b is None:
        fail(f"{name}: in only one of {a_dir}, {b_dir}")
    if a.schema != b.schema:
        fail(f"{name}: schemas differ:\n{a.schema}\nvs\n{b.schema}")
    if a.num_rows != b.num_rows:
        fail(f"{name}: {a.num_rows} rows vs {b.num_rows}")
    for column in a.column_names:
        xs, ys = a.column(column).to_pylist(), b.column(column).to_pylist()
        for i, (x, y) in enumerate(zip(xs, ys)):
            if not same(x, y):
                run = a.column("run")[i].as_py()
                fail(f"{name}: run {run}, column {column!r}: {x!r} vs {y!r}")
    return a.num_rows


def main():
    if len(sys.argv) != 3:
        fail("usage: compare_results.py DIR_A DIR_B")
    a, b = sys.argv[1], sys.argv[2]
    runs = compare(a, b, "summary.parquet")
    if runs == 0:
        fail(f"no summary.parquet in {a} or {b}")
    rows = compare(a, b, "series.parquet")
    print(f"compare_results: {a} and {b} agree: {runs} runs, {rows} series rows "
          f"(wall-clock columns left out)")


if __name__ == "__main__":
    main()
