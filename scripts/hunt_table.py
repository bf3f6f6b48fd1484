#!/usr/bin/env python3
"""The HVT hunt of the default mission over seeds 1..N at one fidelity level: how often the
HVT is captured (with a 95 % Wilson interval) and when, as one Markdown row.

    python3 scripts/hunt_table.py [--binary target/release/vitro] [--seeds 40]
                                  [--level discrete] [--until 3600] [--jobs 2] [--label NAME]
    python3 scripts/hunt_table.py --batch results/mission_hunt [--label NAME]

Each run is `vitro run scenarios/evacuation.toml --json --seed S --fidelity LEVEL --until T`;
with --batch, the runs of a `vitro batch` of experiments/mission_hunt.toml are read instead,
one row per point (lead, search and budget).
"""
import argparse, json, statistics, subprocess, sys
from concurrent.futures import ThreadPoolExecutor

from table_stats import wilson

def run(a, seed):
    p = subprocess.run([a.binary, "run", a.scenario, "--json", "--seed", str(seed),
                        "--fidelity", a.level, "--until", str(a.until)],
                       capture_output=True, text=True)
    if p.returncode not in (0, 4):
        return {"seed": seed, "error": p.stderr.strip()}
    r = json.loads(p.stdout)
    r["seed"] = seed
    return r

def row(label, rs):
    n = len(rs)
    k = sum(1 for r in rs if r["hvt_captured"])
    lo, hi = wilson(k, n)
    ct = [r["hvt_capture_s"] for r in rs if r["hvt_captured"] and r.get("hvt_capture_s") is not None]
    mct = f"{statistics.mean(ct):.0f} (sd {statistics.pstdev(ct):.0f}, median {statistics.median(ct):.0f})" if ct else "-"
    return f"| {label} | {n} | {k}/{n} = {k / max(n, 1):.2f} | {lo:.2f}-{hi:.2f} | {mct} |"

HEAD = "| search | runs | HVT captured | 95% Wilson | mean capture time, s |\n|---|---|---|---|---|"

def batch(a):
    points = {}
    with open(f"{a.batch}/runs.jsonl") as f:
        for line in f:
            r = json.loads(line)
            if r.get("status") != "ok":
                print(f"run {r.get('run')} {r.get('status')}", file=sys.stderr)
                continue
            p = r["params"]
            key = (p.get("pursuit.lead", "determinized"), p.get("pursuit.algorithm", "?"),
                   int(p.get("pursuit.budget", 0)))
            points.setdefault(key, []).append(r["metrics"])
    print(HEAD)
    for (lead, alg, budget), rs in sorted(points.items()):
        print(row(f"{a.label}{lead} {alg}, budget {budget}", rs))
    return 0

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="target/release/vitro")
    ap.add_argument("--scenario", default="scenarios/evacuation.toml")
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--level", default="discrete")
    ap.add_argument("--until", type=float, default=3600.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--label", default="")
    ap.add_argument("--batch", help="a `vitro batch` results folder to read instead of running")
    a = ap.parse_args()
    if a.batch:
        return batch(a)
    with ThreadPoolExecutor(a.jobs) as ex:
        rows = list(ex.map(lambda s: run(a, s), range(1, a.seeds + 1)))
    bad = [r for r in rows if "error" in r]
    for r in bad:
        print(f"seed {r['seed']} failed: {r['error']}", file=sys.stderr)
    rs = [r for r in rows if "error" not in r]
    print(HEAD)
    print(row(f"{a.label} ({a.level})", rs))
    for r in rs:
        print(f"seed {r['seed']}: captured={r['hvt_captured']} at={r.get('hvt_capture_s')} hash={r.get('trace_hash')}", file=sys.stderr)
    return 1 if bad else 0

if __name__ == "__main__":
    sys.exit(main())
