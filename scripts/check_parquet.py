#!/usr/bin/env python3
"""Checks the Parquet tables of a `vitro batch` result directory with pyarrow.

    pip install pyarrow
    python3 scripts/check_parquet.py RESULTS_DIR

summary.parquet must hold one row per run recorded in runs.jsonl, sorted by run, with the
columns run, point, replicate, seed (uint64), one per varied parameter, one per kept metric
(int64, double, bool or string), then status, error (string) and wall_s (double), and agree
with summary.csv; series.parquet (when series are kept) must hold run (uint64), t_s (double)
and one column per series metric. Exits 1 on the first mismatch.
"""
import csv
import json
import math
import sys
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

ALLOWED = {pa.int64(), pa.float64(), pa.bool_(), pa.string()}


def fail(msg):
    print(f"check_parquet: {msg}", file=sys.stderr)
    sys.exit(1)


def expect_columns(table, name, expected):
    got = table.schema.names
    if got != expected:
        fail(f"{name}: columns {got}, expected {expected}")


def expect_type(table, name, column, types):
    t = table.schema.field(column).type
    if t not in types:
        fail(f"{name}: column {column!r} is {t}, expected one of {sorted(map(str, types))}")


def same(a, b):
    """A CSV cell against a Parquet value."""
    if b is None:
        return a == ""
    if isinstance(b, bool):
        return a == str(b).lower()
    if isinstance(b, float):
        return (math.isnan(b) and a == "NaN") or (a != "" and float(a) == b)
    return a == str(b)


def main():
    if len(sys.argv) != 2:
        fail("usage: check_parquet.py RESULTS_DIR")
    d = Path(sys.argv[1])
    manifest = json.loads((d / "manifest.json").read_text())
    params = [p["path"] for p in manifest["parameters"]]
    metrics = manifest["keep"]["metrics"]
    series = manifest["keep"]["series"]
    runs = sorted(json.loads(line)["run"] for line in (d / "runs.jsonl").read_text().splitlines()
                  if line.strip())

    summary = pq.read_table(d / "summary.parquet")
    expect_columns(summary, "summary", ["run", "point", "replicate", "seed", *params, *metrics,
                                        "status", "error", "wall_s"])
    for c in ["run", "point", "replicate", "seed"]:
        expect_type(summary, "summary", c, {pa.uint64()})
    for c in params + metrics:
        expect_type(summary, "summary", c, ALLOWED)
    for c in ["status", "error"]:
        expect_type(summary, "summary", c, {pa.string()})
    expect_type(summary, "summary", "wall_s", {pa.float64()})
    if summary.column("run").to_pylist() != runs:
        fail("summary: the runs differ from runs.jsonl (or are not sorted)")
    statuses = set(summary.column("status").to_pylist())
    if not statuses <= {"ok", "failed"}:
        fail(f"summary: unexpected statuses {statuses}")

    with open(d / "summary.csv", newline="") as f:
        rows = list(csv.reader(f))
    if rows[0] != summary.schema.names or len(rows) - 1 != summary.num_rows:
        fail("summary.csv and summary.parquet differ in columns or rows")
    cols = summary.to_pydict()
    for i, row in enumerate(rows[1:]):
        for name, cell in zip(rows[0], row):
            if not same(cell, cols[name][i]):
                fail(f"row {i}, column {name!r}: CSV {cell!r} vs Parquet {cols[name][i]!r}")

    n_series = 0
    if series:
        s = pq.read_table(d / "series.parquet")
        expect_columns(s, "series", ["run", "t_s", *series])
        expect_type(s, "series", "run", {pa.uint64()})
        expect_type(s, "series", "t_s", {pa.float64()})
        for c in series:
            expect_type(s, "series", c, ALLOWED)
        n_series = s.num_rows

    print(f"check_parquet: {d}: summary {summary.num_rows} rows x {summary.num_columns} columns, "
          f"series {n_series} rows: ok")


if __name__ == "__main__":
    main()
