#!/usr/bin/env python3
"""The default mission at each fidelity level over many seeds: success rate and mean time to
extraction per level, as a Markdown table (and the raw rows as CSV). With `--until 3600`
(the whole hour) its HVT columns measure the hunt.

    cargo build --release -p vitro-cli
    python3 scripts/fidelity_table.py [--seeds 100] [--levels discrete,interpolated,physical]
                                      [--jobs 2] [--until 900] [--out docs/fidelity.csv]
                                      [--calibration scenarios/calibration/evacuation.toml]

Each run is `vitro run scenarios/evacuation.toml --json --seed S --fidelity LEVEL --until T`; seeds
are 1..N, so any row can be re-run alone. With `--calibration FILE` the scenario is run with
`[fidelity] calibration = FILE` (a copy of it next to the original, removed afterwards).
"""
import argparse, csv, json, math, os, statistics, subprocess, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table_stats import wilson, mean_ci
from concurrent.futures import ThreadPoolExecutor

def run(binary, scenario, level, seed, until):
    p = subprocess.run([binary, "run", scenario, "--json", "--seed", str(seed),
                        "--fidelity", level, "--until", str(until)],
                       capture_output=True, text=True)
    if p.returncode not in (0, 4):
        return {"level": level, "seed": seed, "error": p.stderr.strip()}
    r = json.loads(p.stdout)
    r["level"] = level
    r["seed"] = seed
    return r

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="target/release/vitro")
    ap.add_argument("--scenario", default="scenarios/evacuation.toml")
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--levels", default="discrete,interpolated,physical")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--until", type=float, default=900.0,
                    help="simulated seconds per run (the escort is over by 900 s)")
    ap.add_argument("--out", default=None)
    ap.add_argument("--calibration", default=None,
                    help="calibration file (made by `vitro calibrate`) the abstract levels use")
    a = ap.parse_args()
    tmp = None
    if a.calibration:
        d = os.path.dirname(os.path.abspath(a.scenario))
        rel = os.path.relpath(os.path.abspath(a.calibration), d)
        text = open(a.scenario).read()
        if "\n[fidelity]\n" not in text:
            sys.exit("the scenario has no [fidelity] table")
        text = text.replace("\n[fidelity]\n", f"\n[fidelity]\ncalibration = \"{rel}\"\n", 1)
        tmp = os.path.join(d, f".calibrated-{os.getpid()}.toml")
        open(tmp, "w").write(text)
        a.scenario = tmp
    try:
        return table(a)
    finally:
        if tmp:
            os.remove(tmp)

def table(a):
    levels = a.levels.split(",")
    jobs = [(l, s) for l in levels for s in range(1, a.seeds + 1)]
    with ThreadPoolExecutor(a.jobs) as ex:
        rows = list(ex.map(lambda j: run(a.binary, a.scenario, *j, a.until), jobs))
    errors = [r for r in rows if "error" in r]
    for e in errors:
        print(f"run {e['level']} seed {e['seed']} failed: {e['error']}", file=sys.stderr)
    print("| level | runs | success rate [Wilson 95% CI] | mean time to extraction, s ± 95% CI (sd) | casualties / run | HVT captured | mean capture time, s | sim s per wall s |")
    print("|---|---|---|---|---|---|---|---|")
    for l in levels:
        rs = [r for r in rows if r["level"] == l and "error" not in r]
        if not rs:
            continue
        n = len(rs)
        k = sum(1 for r in rs if r["success"])
        p = k / n
        lo, hi = wilson(k, n)
        t = [r["time_to_extraction_s"] for r in rs if r["success"]]
        mean, ci = mean_ci(t)
        mt = f"{mean:.1f} ± {ci:.1f} ({statistics.pstdev(t):.1f})" if len(t) > 1 else "-"
        cas = statistics.mean(r["casualties"] for r in rs)
        hvt = sum(1 for r in rs if r["hvt_captured"]) / n
        ct = [r["hvt_capture_s"] for r in rs if r["hvt_captured"] and r.get("hvt_capture_s")]
        mct = f"{statistics.mean(ct):.0f}" if ct else "-"
        speed = statistics.median(r["sim_s_per_wall_s"] for r in rs)
        print(f"| {l} | {n} | {p:.2f} [{lo:.2f}, {hi:.2f}] | {mt} | {cas:.2f} | {hvt:.2f} | {mct} | {speed:.0f} |")
    # The abstract levels against the physical one, seed by seed (seeds where both succeed).
    conc = {r["seed"]: r for r in rows if r["level"] == "physical" and "error" not in r}
    for l in levels:
        if l == "physical" or not conc:
            continue
        pairs = [(r["time_to_extraction_s"], conc[r["seed"]]["time_to_extraction_s"])
                 for r in rows if r["level"] == l and "error" not in r and r["success"]
                 and r["seed"] in conc and conc[r["seed"]]["success"]]
        if len(pairs) < 2:
            continue
        d, ci = mean_ci([x - y for x, y in pairs])
        base = statistics.mean(y for _, y in pairs)
        print(f"\n{l} - physical, paired over {len(pairs)} seeds: {d:+.1f} ± {ci:.1f} s "
              f"({100 * d / base:+.1f} % ± {100 * ci / base:.1f} % of {base:.1f} s)")
    if a.out:
        keys = ["level", "seed", "success", "time_to_extraction_s", "casualties",
                "adversaries_detected", "time_uncovered_s", "hvt_captured", "messages_sent",
                "events", "sim_time_s", "wall_time_s", "sim_s_per_wall_s", "trace_hash"]
        with open(a.out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
            w.writeheader()
            for r in rows:
                if "error" not in r:
                    w.writerow(r)
    return 1 if errors else 0

if __name__ == "__main__":
    sys.exit(main())
