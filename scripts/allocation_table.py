#!/usr/bin/env python3
"""The table of the surveillance allocation experiment: per allocation method and radio loss,
the means over the runs with 95% confidence intervals (Student t) and n.

    python3 scripts/allocation_table.py results/surveillance_allocation/summary.csv

Reads the summary.csv `vitro batch experiments/surveillance_allocation.toml` writes; prints a
Markdown table. Runs that failed, and a metric a run lacks (NaN), are left out of that mean.
"""

import sys
from collections import defaultdict

from surveillance_table import mean_ci, number

METHODS = ["contract-net", "auction", "central"]


def main(path):
    points = defaultdict(list)
    with open(path) as f:
        import csv

        for row in csv.DictReader(f):
            if row["status"] == "ok":
                points[(row["allocation.method"], float(row["channel.loss"]))].append(row)
    print("| method | radio loss | runs | restricted mean time to detection, s "
          "| mean tracked share | red units detected (of 8) | allocation messages "
          "| all messages | calls (rounds, plans) | failed | re-allocations "
          "| sectors held at the end |")
    print("|---|---:|---:|---|---|---|---|---|---|---|---|---|")
    order = lambda p: (METHODS.index(p[0]) if p[0] in METHODS else len(METHODS), p[0], p[1])
    for (method, loss) in sorted(points, key=order):
        rows = points[(method, loss)]
        cell = {k: mean_ci([number(r, k) for r in rows]) for k in (
            "restricted_time_to_detection_s", "mean_tracked_share", "red_detected",
            "allocation_messages", "messages_sent", "calls", "calls_failed", "reallocations",
            "sectors_held")}
        fmt = lambda k, d: f"{cell[k][0]:.{d}f} ± {cell[k][1]:.{d}f}"
        print(f"| {method} | {loss:.1f} | {len(rows)} "
              f"| {fmt('restricted_time_to_detection_s', 0)} | {fmt('mean_tracked_share', 3)} "
              f"| {fmt('red_detected', 2)} | {fmt('allocation_messages', 0)} "
              f"| {fmt('messages_sent', 0)} | {fmt('calls', 1)} | {fmt('calls_failed', 1)} "
              f"| {fmt('reallocations', 1)} | {fmt('sectors_held', 1)} |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "results/surveillance_allocation/summary.csv")
