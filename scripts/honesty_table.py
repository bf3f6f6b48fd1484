#!/usr/bin/env python3
"""Summarises runs of experiments/mission_honesty.toml (radio loss x camera range): per point,
the success rate (Wilson 95 % interval), the mean time to extraction (successful runs), the
mean time uncovered and the mean number of adversaries detected (mean +- 1.96 standard
errors), and n. With two result directories,
prints both side by side (e.g. before and after a change).

Usage: python3 scripts/honesty_table.py RESULTS_DIR [OTHER_RESULTS_DIR]
"""

import csv
import math
import pathlib
import sys

from table_stats import wilson, mean_ci, num

KEYS = ("channel.loss", "sensors.air.range_m", "sensors.ground.range_m")








def summary(results: pathlib.Path) -> dict:
    rows = list(csv.DictReader(open(results / "summary.csv")))
    points: dict = {}
    for r in rows:
        if r.get("status", "ok") not in ("ok", ""):
            continue
        key = tuple(float(r[k]) for k in KEYS)
        points.setdefault(key, []).append(r)
    out = {}
    for key, rs in sorted(points.items()):
        n = len(rs)
        ok = sum(r["success"].lower() == "true" for r in rs)
        lo, hi = wilson(ok, n)
        unc = mean_ci([num(r["time_uncovered_s"]) for r in rs])
        det = mean_ci([num(r["adversaries_detected"]) for r in rs])
        tte = mean_ci([num(r["time_to_extraction_s"]) for r in rs])
        out[key] = (n, ok / n, lo, hi, unc, det, tte)
    return out


def cell(v) -> str:
    n, p, lo, hi, unc, det, tte = v
    return (f"{p:.2f} [{lo:.2f}, {hi:.2f}] | {tte[0]:.0f} ± {tte[1]:.0f} | "
            f"{unc[0]:.0f} ± {unc[1]:.0f} | {det[0]:.1f} ± {det[1]:.1f} | {n}")


def main() -> int:
    dirs = [pathlib.Path(a) for a in sys.argv[1:3]]
    if not dirs:
        print(__doc__)
        return 2
    tables = [summary(d) for d in dirs]
    head = "| loss | air camera m | ground camera m |"
    cols = " success [95 % CI] | extraction s | uncovered s | detected | n |"
    if len(tables) == 1:
        print(head + cols)
        print("|---" * 8 + "|")
    else:
        print(head + cols.replace(" |", " (1) |") + cols.replace(" |", " (2) |"))
        print("|---" * 13 + "|")
    for key in tables[0]:
        line = f"| {key[0]:.1f} | {key[1]:.0f} | {key[2]:.0f} | " + " | ".join(
            cell(t[key]) if key in t else "- | - | - | - | -" for t in tables)
        print(line + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
