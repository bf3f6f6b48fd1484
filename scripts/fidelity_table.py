#!/usr/bin/env python3
"""The default mission at each fidelity level over many seeds: the success rate, the mean time
to extraction and, per abstract level, its gap to the physical level over the seeds where both
reach extraction, as one Markdown table (and every run as a CSV row).

    cargo build --release -p vitro-cli
    python3 scripts/fidelity_table.py [--seeds 100] [--levels discrete,interpolated,physical]
                                      [--jobs 2] [--until 900] [--out docs/fidelity.csv]
                                      [--calibration scenarios/calibration/evacuation.toml
                                       [--uncalibrated-too]]
    python3 scripts/fidelity_table.py --read docs/fidelity.csv
                                      [--read-calibrated docs/fidelity_calibrated.csv]

Each run is `vitro run scenarios/evacuation.toml --json --seed S --fidelity LEVEL --until T`; seeds
are 1..N, so any row can be re-run alone. With `--calibration FILE` the abstract levels run the
scenario with `[fidelity] calibration = FILE` (a copy of it next to the original, removed
afterwards; the physical level never reads it); with `--uncalibrated-too` they also run without
it, and the table has both rows. With `--read` (runs made without a calibration) and
`--read-calibrated` (runs of the abstract levels made with one), it runs nothing and prints the
table of the runs those CSV files (written by `--out`) hold. Prints the table only; failed runs
go to stderr (exit 1).
"""
import argparse, csv, json, os, statistics, subprocess, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table_stats import wilson, mean_ci
from concurrent.futures import ThreadPoolExecutor

ABSTRACT = ("discrete", "interpolated")


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


def calibrated_copy(scenario, calibration):
    d = os.path.dirname(os.path.abspath(scenario))
    rel = os.path.relpath(os.path.abspath(calibration), d)
    text = open(scenario).read()
    if "\n[fidelity]\n" not in text:
        sys.exit("the scenario has no [fidelity] table")
    text = text.replace("\n[fidelity]\n", f"\n[fidelity]\ncalibration = \"{rel}\"\n", 1)
    tmp = os.path.join(d, f".calibrated-{os.getpid()}.toml")
    open(tmp, "w").write(text)
    return tmp


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="target/release/vitro")
    ap.add_argument("--scenario", default="scenarios/evacuation.toml")
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--levels", default="discrete,interpolated,physical")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--until", type=float, default=900.0,
                    help="simulated seconds per run (the escort is over by 900 s)")
    ap.add_argument("--out", default=None, help="write every run as a CSV row")
    ap.add_argument("--calibration", default=None,
                    help="calibration file (made by `vitro calibrate`) the abstract levels use")
    ap.add_argument("--uncalibrated-too", action="store_true",
                    help="with --calibration: run the abstract levels without it as well")
    ap.add_argument("--read", help="print the table of the runs in this CSV file; run nothing")
    ap.add_argument("--read-calibrated", help="with --read: runs of calibrated abstract levels")
    a = ap.parse_args()
    if a.uncalibrated_too and not a.calibration:
        ap.error("--uncalibrated-too needs --calibration")
    if a.read:
        return read(a.read, a.read_calibrated)
    tmp = calibrated_copy(a.scenario, a.calibration) if a.calibration else None
    try:
        return table(a, tmp)
    finally:
        if tmp:
            os.remove(tmp)


def table(a, calibrated):
    # (label, level, scenario, calibration) per row of the table, in its order.
    variants = []
    for level in a.levels.split(","):
        if level in ABSTRACT and calibrated:
            if a.uncalibrated_too:
                variants.append((f"{level}, uncalibrated", level, a.scenario, ""))
            variants.append((f"{level}, calibrated", level, calibrated, a.calibration))
        elif level in ABSTRACT:
            variants.append((f"{level}, uncalibrated", level, a.scenario, ""))
        else:
            variants.append((level, level, a.scenario, ""))
    variants.sort(key=lambda v: (v[1] not in ABSTRACT, v[3] != "", ABSTRACT.index(v[1]) if v[1] in ABSTRACT else 0))
    jobs = [(v, s) for v in variants for s in range(1, a.seeds + 1)]

    def one(job):
        (label, level, scenario, calibration), seed = job
        r = run(a.binary, scenario, level, seed, a.until)
        r["label"], r["calibration"] = label, calibration
        return r

    with ThreadPoolExecutor(a.jobs) as ex:
        rows = list(ex.map(one, jobs))
    errors = [r for r in rows if "error" in r]
    for e in errors:
        print(f"run {e['label']} seed {e['seed']} failed: {e['error']}", file=sys.stderr)
    ok = [r for r in rows if "error" not in r]
    print("\n".join(render(variants, ok)))
    if a.out:
        keys = ["level", "seed", "success", "time_to_extraction_s", "casualties",
                "adversaries_detected", "time_uncovered_s", "hvt_captured", "messages_sent",
                "events", "sim_time_s", "wall_time_s", "sim_s_per_wall_s", "trace_hash"]
        with open(a.out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
            w.writeheader()
            for r in ok:
                w.writerow(r)
    return 1 if errors else 0


def read(plain, calibrated):
    """Prints the table of the runs in the CSV files (uncalibrated, then calibrated)."""
    rows, variants = [], []
    for path, cal in ((plain, False), (calibrated, True)):
        if not path:
            continue
        for r in csv.DictReader(open(path)):
            level = r["level"]
            label = level if level not in ABSTRACT else f"{level}, {'calibrated' if cal else 'uncalibrated'}"
            if (label, level) not in variants:
                variants.append((label, level))
            t = r["time_to_extraction_s"]
            rows.append({"label": label, "level": level, "seed": int(r["seed"]),
                         "success": r["success"] == "True", "time_to_extraction_s": float(t) if t else None})
    variants.sort(key=lambda v: (v[1] not in ABSTRACT, v[0].endswith(", calibrated"),
                                 ABSTRACT.index(v[1]) if v[1] in ABSTRACT else 0))
    print("\n".join(render(variants, rows)))
    return 0


def render(variants, ok):
    """The table's lines: one row per (label, level, ...) variant of the runs `ok`."""
    lines = ["| level | runs | success rate [Wilson 95 %] | time to extraction, s (mean ± 95 % CI) "
             "| vs physical, paired seeds |", "|---|---|---|---|---|"]
    physical = {r["seed"]: r for r in ok if r["level"] == "physical"}
    for label, level, *_ in variants:
        rs = [r for r in ok if r["label"] == label]
        if not rs:
            continue
        n = len(rs)
        k = sum(1 for r in rs if r["success"])
        lo, hi = wilson(k, n)
        mean, ci = mean_ci([r["time_to_extraction_s"] for r in rs if r["success"]])
        t = f"{mean:.1f} ± {ci:.1f}" if k > 1 else "-"
        pairs = [(r["time_to_extraction_s"], physical[r["seed"]]["time_to_extraction_s"])
                 for r in rs if r["success"] and r["seed"] in physical
                 and physical[r["seed"]]["success"]]
        if level == "physical" or len(pairs) < 2:
            gap = "—"
        else:
            d, dci = mean_ci([x - y for x, y in pairs])
            base = statistics.mean(y for _, y in pairs)
            gap = (f"{d:+.1f} ± {dci:.1f} s ({100 * d / base:+.1f} % ± {100 * dci / base:.1f} %), "
                   f"{len(pairs)} seeds").replace("-", "−")
        lines.append(f"| {label} | {n} | {k / n:.2f} [{lo:.2f}, {hi:.2f}] | {t} | {gap} |")
    return lines


if __name__ == "__main__":
    sys.exit(main())
