#!/usr/bin/env python3
"""The table of the traffic experiment: per level of fidelity, trips, stalls and waits over
the runs, with 95 % intervals and n.

    python3 scripts/traffic_table.py results/traffic_levels/summary.csv

Reads the summary.csv `vitro batch experiments/traffic_levels.toml` writes; prints a Markdown
table. Stalls per 20 vehicle-hours are pooled over the runs (all stalls over all
vehicle-hours) with the exact Poisson 95 % interval of the count; the other columns are means
over the runs with 1.96 standard errors. Trip time against the discrete level pairs each
run with the discrete run of the same seed (the experiment uses common random numbers: the
same starts and destinations at every level).
"""

import csv
import math
import sys
from collections import defaultdict

from table_stats import mean_ci, num

LEVELS = ["discrete", "interpolated", "physical"]


def log_poisson_cdf(k: int, mu: float) -> float:
    """log P(X <= k) for X ~ Poisson(mu), summed in log space."""
    if mu == 0:
        return 0.0
    terms = [i * math.log(mu) - mu - math.lgamma(i + 1) for i in range(k + 1)]
    top = max(terms)
    return top + math.log(sum(math.exp(t - top) for t in terms))


def poisson_ci(k: int) -> tuple[float, float]:
    """The exact (Garwood) 95 % interval of a Poisson mean from one count k."""

    def solve(target, want_upper):
        lo, hi = 0.0, max(10.0, 3.0 * k + 20.0)
        for _ in range(200):
            mid = (lo + hi) / 2
            if want_upper:
                # P(X <= k | mu) = 0.025
                below = log_poisson_cdf(k, mid) > math.log(target)
            else:
                # P(X >= k | mu) = 0.025, i.e. P(X <= k - 1 | mu) = 0.975
                below = log_poisson_cdf(k - 1, mid) > math.log(1 - target)
            lo, hi = (mid, hi) if below else (lo, mid)
        return (lo + hi) / 2

    lower = 0.0 if k == 0 else solve(0.025, False)
    return lower, solve(0.025, True)


def cell(m, h, digits=1):
    if math.isnan(m):
        return "—"
    if math.isnan(h):
        return f"{m:.{digits}f}"
    return f"{m:.{digits}f} ± {h:.{digits}f}"


def main(path):
    runs = defaultdict(dict)
    for row in csv.DictReader(open(path)):
        if row.get("status", "ok") == "ok":
            runs[row["fidelity.level"]][row["seed"]] = row
    print("| level | runs | trips completed | stalls per 20 vehicle-hours (pooled, exact 95 %) "
          "| vehicles that stalled | mean trip, s | trip time vs discrete, same seed "
          "| longest wait, s (mean; max) | collisions |")
    print("|---|---:|---|---|---|---|---|---|---|")
    base = runs.get("discrete", {})
    for level in LEVELS:
        rows = runs.get(level)
        if not rows:
            continue
        rs = list(rows.values())
        stalls = sum(int(num(r["stalls"])) for r in rs)
        vh = sum(num(r["vehicle_hours"]) for r in rs)
        lo, hi = poisson_ci(stalls)
        rate = f"{20 * stalls / vh:.2f} [{20 * lo / vh:.2f}, {20 * hi / vh:.2f}] ({stalls} in {vh:.0f} h)"
        ratios = [num(r["mean_trip_s"]) / num(base[s]["mean_trip_s"]) - 1
                  for s, r in rows.items() if s in base and num(base[s]["mean_trip_s"]) > 0]
        m, h = mean_ci(ratios)
        vs = "—" if level == "discrete" else f"{100 * m:+.1f} % ± {100 * h:.1f} %"
        waits = [num(r["deadlock_s"]) for r in rs]
        wm, wh = mean_ci(waits)
        collisions = [r.get("collisions", "") for r in rs]
        coll = "not measured" if all(c in ("", "NaN", "nan") for c in collisions) else \
            cell(*mean_ci([num(c) for c in collisions]))
        print(f"| {level} | {len(rs)} | {cell(*mean_ci([num(r['trips_completed']) for r in rs]))} "
              f"| {rate} | {cell(*mean_ci([num(r['vehicles_stalled']) for r in rs]))} "
              f"| {cell(*mean_ci([num(r['mean_trip_s']) for r in rs]))} | {vs} "
              f"| {cell(wm, wh, 0)}; {max(waits):.0f} | {coll} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
