#!/usr/bin/env python3
"""Where the time to extraction goes, phase by phase: the default mission's commander phase
log at each level (the `evac_timeline` example), abstract minus physical per phase, paired
seeds, as a Markdown table.

    cargo build --release -p vitro-evac --example evac_timeline
    python3 scripts/phase_table.py [--seeds 20] [--jobs 2] [--levels discrete,interpolated]
                                   [--calibration scenarios/calibration/evacuation.toml
                                    [--uncalibrated-too]]

Phases: the drive out (Out), the squad's walk to the VIP and the wait there (Pickup), the
walk back with the VIP (Escort), boarding, the drive to extraction (Back). Only seeds where
both levels reach extraction count; a phase the same on every seed is shown without its
interval. With `--calibration FILE` the abstract levels use it (a copy of the scenario next to
the original, removed afterwards); with `--uncalibrated-too` they also run without it, one row
each. Prints the table only.
"""
import argparse, json, os, subprocess, sys
from concurrent.futures import ThreadPoolExecutor
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table_stats import mean_ci

PHASES = ["Out", "Pickup", "Escort", "Boarding", "Back"]
HEADS = ["drive out", "squad to the VIP (+30 s wait)", "squad back with the VIP", "boarding",
         "drive to extraction"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="target/release/examples/evac_timeline")
    ap.add_argument("--scenario", default="scenarios/evacuation.toml")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--levels", default="discrete,interpolated")
    ap.add_argument("--calibration", default=None)
    ap.add_argument("--uncalibrated-too", action="store_true",
                    help="with --calibration: run the abstract levels without it as well")
    a = ap.parse_args()
    if a.uncalibrated_too and not a.calibration:
        ap.error("--uncalibrated-too needs --calibration")
    tmp = None
    scenario = a.scenario
    if a.calibration:
        d = os.path.dirname(os.path.abspath(a.scenario))
        rel = os.path.relpath(os.path.abspath(a.calibration), d)
        text = open(a.scenario).read()
        text = text.replace("\n[fidelity]\n", f"\n[fidelity]\ncalibration = \"{rel}\"\n", 1)
        tmp = os.path.join(d, f".phases-{os.getpid()}.toml")
        open(tmp, "w").write(text)
        scenario = tmp
    levels = a.levels.split(",")
    # (label, level, scenario) per row, then the physical runs they are compared with.
    rows = []
    if a.uncalibrated_too or not a.calibration:
        rows += [(f"{l}, uncalibrated", l, a.scenario) for l in levels]
    if a.calibration:
        rows += [(f"{l}, calibrated", l, scenario) for l in levels]
    variants = rows + [("physical", "physical", a.scenario)]
    jobs = [(v, s) for v in variants for s in range(1, a.seeds + 1)]

    def run(job):
        (label, l, sc), s = job
        p = subprocess.run([a.binary, l, str(s), sc], capture_output=True, text=True)
        if p.returncode != 0:
            print(f"{label} seed {s} failed: {p.stderr.strip()}", file=sys.stderr)
        return (label, s), (json.loads(p.stdout) if p.returncode == 0 else None)

    try:
        with ThreadPoolExecutor(a.jobs) as ex:
            out = dict(ex.map(run, jobs))
    finally:
        if tmp:
            os.remove(tmp)
    print("| level | seeds | " + " | ".join(HEADS) + " | total |")
    print("|---|---" + "|---" * (len(PHASES) + 1) + "|")
    for label, _, _ in rows:
        diffs = {p: [] for p in PHASES + ["total"]}
        n = 0
        for s in range(1, a.seeds + 1):
            x, y = out.get((label, s)), out.get(("physical", s))
            if not (x and y and x["success"] and y["success"]):
                continue
            n += 1
            for p in PHASES:
                diffs[p].append(x["phases"].get(p, 0.0) - y["phases"].get(p, 0.0))
            diffs["total"].append(x["time_to_extraction_s"] - y["time_to_extraction_s"])
        cells = []
        for p in PHASES + ["total"]:
            m, h = mean_ci(diffs[p])
            cell = f"{m:+.1f}" if not h > 0.05 else f"{m:+.1f} ± {h:.1f}"
            cells.append(cell.replace("-", "−"))
        print(f"| {label} | {n} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
