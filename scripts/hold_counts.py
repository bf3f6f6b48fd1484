#!/usr/bin/env python3
"""The hold benchmark counted, not timed: instructions, cache misses and mispredicted
branches per event of each part, under cachegrind (deterministic, so a loaded machine
cannot disturb it).

    python3 scripts/hold_counts.py [--pending 1000] [--events 200000] HOLD_BIN [HOLD_BIN ...]

HOLD_BIN is a build of `cargo build --release -p vitro --example hold`. Each part
(`--only simulation|floor|queue`) runs twice, with EVENTS and 2 x EVENTS events, and the
difference divided by EVENTS is the cost per event in steady state (set-up and the first
events cancel out). The simulated caches are this machine's (AMD EPYC): a 32 KiB 8-way first
level and a 512 KiB 8-way second level (cachegrind's "LL"). Needs valgrind.
"""

import argparse
import os
import subprocess
import sys
import tempfile

CACHES = ["--I1=32768,8,64", "--D1=32768,8,64", "--LL=524288,8,64"]


def counts(binary, part, pending, events):
    """Totals of (Ir, D1 misses, LL misses, mispredicts) for one run of one part."""
    with tempfile.NamedTemporaryFile(suffix=".cg") as out:
        subprocess.run(
            ["valgrind", "--tool=cachegrind", "--cache-sim=yes", "--branch-sim=yes",
             f"--cachegrind-out-file={out.name}", *CACHES,
             binary, str(pending), str(events), "--only", part],
            check=True, capture_output=True,
        )
        events_line = summary = None
        for line in open(out.name):
            if line.startswith("events:"):
                events_line = line.split()[1:]
            elif line.startswith("summary:"):
                summary = [int(x) for x in line.split()[1:]]
    c = dict(zip(events_line, summary))
    d1 = c.get("D1mr", 0) + c.get("D1mw", 0)
    ll = c.get("DLmr", 0) + c.get("DLmw", 0)
    mis = c.get("Bcm", 0) + c.get("Bim", 0)
    return c["Ir"], d1, ll, mis


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binaries", nargs="+")
    ap.add_argument("--pending", type=int, default=1000)
    ap.add_argument("--events", type=int, default=200_000)
    ap.add_argument("--parts", default="simulation,floor,queue")
    a = ap.parse_args()
    for b in a.binaries:
        if not os.access(b, os.X_OK):
            sys.exit(f"hold_counts: {b} is not an executable")
    print(f"pending {a.pending}, per event over {a.events} events")
    print(f"{'binary':<40} {'part':<11} {'instr':>7} {'L1 miss':>8} {'L2 miss':>8} {'mispred':>8}")
    for b in a.binaries:
        for part in a.parts.split(","):
            one = counts(b, part, a.pending, a.events)
            two = counts(b, part, a.pending, 2 * a.events)
            per = [(y - x) / a.events for x, y in zip(one, two)]
            print(f"{b[-40:]:<40} {part:<11} {per[0]:>7.1f} {per[1]:>8.3f} {per[2]:>8.3f} {per[3]:>8.3f}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
