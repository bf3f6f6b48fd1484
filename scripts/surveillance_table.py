#!/usr/bin/env python3
"""The table of the surveillance experiment: per UAV count and radio loss, the means over the
runs with 95% confidence intervals (Student t) and n.

    python3 scripts/surveillance_table.py results/surveillance_uavs/summary.csv

Reads the summary.csv `vitro batch experiments/surveillance_uavs.toml` writes; prints a
Markdown table. Runs that failed, and a metric a run lacks (NaN), are left out of that mean.
"""

import csv
import math
import sys
from collections import defaultdict

# Two-sided 95% quantiles of Student's t by degrees of freedom (interpolated between).
T975 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306,
        9: 2.262, 10: 2.228, 15: 2.131, 20: 2.086, 25: 2.060, 30: 2.042, 40: 2.021, 49: 2.010,
        60: 2.000, 120: 1.980}


def t975(df):
    if df in T975:
        return T975[df]
    keys = sorted(T975)
    for a, b in zip(keys, keys[1:]):
        if a < df < b:
            return T975[a] + (T975[b] - T975[a]) * (df - a) / (b - a)
    return 1.960


def mean_ci(xs):
    """Mean, half-width of its 95% interval, n (NaN values left out)."""
    xs = [x for x in xs if not math.isnan(x)]
    n = len(xs)
    if n == 0:
        return float("nan"), float("nan"), 0
    m = sum(xs) / n
    if n < 2:
        return m, float("nan"), n
    s = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
    return m, t975(n - 1) * s / math.sqrt(n), n


def number(row, key):
    v = row.get(key, "")
    return float(v) if v not in ("", "NaN", "nan") else float("nan")


def main(path):
    points = defaultdict(list)
    for row in csv.DictReader(open(path)):
        if row["status"] == "ok":
            points[(int(row["entity.0.count"]), float(row["channel.loss"]))].append(row)
    print("| UAVs | radio loss | runs | mean time to first detection, s (detected units; n runs) "
          "| restricted mean time to detection, s | mean tracked share | red units detected (of 8) "
          "| calls failed | re-allocations | of them handovers | UAVs presumed lost |")
    print("|---:|---:|---:|---|---|---|---|---|---|---|---|")
    for (uavs, loss), rows in sorted(points.items()):
        cell = {k: mean_ci([number(r, k) for r in rows]) for k in (
            "mean_time_to_detection_s", "restricted_time_to_detection_s", "mean_tracked_share",
            "red_detected", "calls_failed", "reallocations", "handovers", "presumed_lost")}
        t = cell["mean_time_to_detection_s"]
        fmt = lambda k, d: f"{cell[k][0]:.{d}f} ± {cell[k][1]:.{d}f}"
        print(f"| {uavs} | {loss:.1f} | {len(rows)} | {t[0]:.0f} ± {t[1]:.0f} (n={t[2]}) "
              f"| {fmt('restricted_time_to_detection_s', 0)} | {fmt('mean_tracked_share', 3)} "
              f"| {fmt('red_detected', 2)} | {fmt('calls_failed', 1)} | {fmt('reallocations', 1)} "
              f"| {fmt('handovers', 1)} "
              f"| {fmt('presumed_lost', 2)} |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "results/surveillance_uavs/summary.csv")
