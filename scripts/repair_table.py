#!/usr/bin/env python3
"""Summarises runs of experiments/mission_repair.toml or mission_repair_depth.toml: per point
(strategy, failure rate, team size, depth bound), the means of the cover plan's failures,
repairs, cuts, fall-backs, plan messages, plan messages per repair and checkpoints missed
(mean +- 1.96 standard errors), the success rate (Wilson 95 % interval) and n.

Usage: python3 scripts/repair_table.py RESULTS_DIR
"""

import csv
import math
import pathlib
import sys

from table_stats import wilson, mean_ci, num

KEYS = ("repair.strategy", "repair.failure_rate", "entity.7.count", "repair.max_depth")
COLUMNS = (
    "plan_failures",
    "plan_repairs",
    "plan_cuts",
    "plan_fallbacks",
    "plan_messages",
    "checkpoints_missed",
    "time_uncovered_s",
)
ORDER = {"replan": 0, "back_on_track": 1, "lazy": 2, "repeated_lazy": 3}








def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    results = pathlib.Path(sys.argv[1])
    try:
        rows = list(csv.DictReader(open(results / "summary.csv")))
    except OSError as e:
        print(f"{results}: {e}", file=sys.stderr)
        return 2
    points: dict = {}
    for r in rows:
        if r.get("status", "ok") not in ("ok", ""):
            continue
        key = tuple(r.get(k, "") for k in KEYS)
        points.setdefault(key, []).append(r)
    names = [k.split(".")[-1] if k != "entity.7.count" else "vidars" for k in KEYS]
    head = names + ["n", "success"] + list(COLUMNS) + ["messages/repair"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))

    def order(item):
        (s, rate, team, depth), _ = item
        return (num(team), num(depth), num(rate), ORDER.get(s, 9))

    for key, rs in sorted(points.items(), key=order):
        n = len(rs)
        ok = sum(r["success"].lower() == "true" for r in rs)
        lo, hi = wilson(ok, n)
        cells = [k if k != "" else "-" for k in key] + [str(n), f"{ok / n:.2f} [{lo:.2f}, {hi:.2f}]"]
        for c in COLUMNS:
            m, h = mean_ci([num(r.get(c)) for r in rs])
            cells.append(f"{m:.2f} ± {h:.2f}")
        per = [
            num(r["plan_messages"]) / num(r["plan_repairs"])
            for r in rs
            if num(r.get("plan_repairs")) > 0
        ]
        m, h = mean_ci(per)
        cells.append(f"{m:.2f} ± {h:.2f} (n={len(per)})")
        print("| " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
