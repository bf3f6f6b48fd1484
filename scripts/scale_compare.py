#!/usr/bin/env python3
"""Two builds of the scaling table side by side: interleaved rounds, medians.

    python3 scripts/scale_compare.py BEFORE_BIN AFTER_BIN [--rounds 5] [--sizes 150,500,2000]
        [--until 600] [--levels discrete]

BEFORE_BIN and AFTER_BIN are `scale_table` example binaries (`cargo build --release -p
vitro-evac --example scale_table`, copied aside). Each round runs both (the order swapped
every round); each row is a child process of its own. Prints, per level and entity count,
the events, the median CPU µs per event with its range, the median simulated seconds per CPU
second (the run's thread), and whether every run of both binaries gave the same trace hash.
"""

import argparse
import statistics
import subprocess
import sys


def run(binary, sizes, until, levels):
    out = subprocess.run(
        [binary, "--sizes", sizes, "--until", str(until), "--levels", levels],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    rows = []
    for line in out.splitlines()[1:]:
        f = line.split()
        # level entities [blocks] events wall µs/ev sim/wall cpu cpu-µs/ev setup peak sim
        # hash (older builds print no blocks column)
        if len(f) == 13:
            del f[2]
        if len(f) != 12:
            continue
        rows.append(
            {
                "level": f[0],
                "entities": int(f[1]),
                "events": int(f[2]),
                "cpu_s": float(f[6]),
                "cpu_us": float(f[7]),
                "rss": float(f[9]),
                "sim_s": float(f[10]),
                "hash": f[11],
            }
        )
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--sizes", default="150,500,2000")
    ap.add_argument("--until", type=float, default=600)
    ap.add_argument("--levels", default="discrete")
    a = ap.parse_args()
    got = {"before": [], "after": []}
    for r in range(a.rounds):
        order = ["before", "after"] if r % 2 == 0 else ["after", "before"]
        for name in order:
            got[name].extend(run(getattr(a, name), a.sizes, a.until, a.levels))
        print(f"round {r + 1} of {a.rounds} done", file=sys.stderr)
    keys = sorted({(x["level"], x["entities"]) for x in got["before"] + got["after"]})
    print(
        "| level, entities | events | CPU µs per event, before → after (range) "
        "| sim s per CPU s, before → after | ratio | peak RSS MiB | trace hash |"
    )
    print("|---|---:|---:|---:|---:|---:|---|")
    for level, n in keys:
        b = [x for x in got["before"] if (x["level"], x["entities"]) == (level, n)]
        f = [x for x in got["after"] if (x["level"], x["entities"]) == (level, n)]
        hashes = {x["hash"] for x in b + f}
        events = {x["events"] for x in b + f}
        mb = statistics.median(x["cpu_us"] for x in b)
        ma = statistics.median(x["cpu_us"] for x in f)
        sb = statistics.median(x["sim_s"] / x["cpu_s"] for x in b)
        sa = statistics.median(x["sim_s"] / x["cpu_s"] for x in f)
        rng = lambda xs: f"{min(x['cpu_us'] for x in xs):.2f}–{max(x['cpu_us'] for x in xs):.2f}"
        print(
            f"| {level}, {n:,} | {'/'.join(f'{e:,}' for e in sorted(events))} "
            f"| {mb:.2f} ({rng(b)}) → {ma:.2f} ({rng(f)}) | {sb:,.0f} → {sa:,.0f} "
            f"| {mb / ma:.2f}× | {statistics.median(x['rss'] for x in f):.0f} "
            f"| {'`' + hashes.pop() + '`' if len(hashes) == 1 else 'DIFFER: ' + ' '.join(sorted(hashes))} |"
        )


if __name__ == "__main__":
    main()
