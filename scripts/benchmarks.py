#!/usr/bin/env python3
"""Runs Vitro's benchmark programs and (re)writes their tables in docs/benchmarks.md.

    python3 scripts/benchmarks.py                      # every table, full sizes
    python3 scripts/benchmarks.py --only hold,scale    # some tables
    python3 scripts/benchmarks.py --quick              # tiny sizes: checks the script, not figures
    python3 scripts/benchmarks.py --list               # the tables and their commands

Each table sits in docs/benchmarks.md between two markers,

    <!-- benchmarks.py: NAME -->
    ...
    <!-- /benchmarks.py: NAME -->

and is replaced as a whole: the machine, the command, the table and the ratios, all from the
programs' own output. Text outside the markers is left alone. The examples are built in
release first (`cargo build --release -p CRATE --example NAME`, not timed), then run from
`target/release/examples` (or `$CARGO_TARGET_DIR`). A table whose program fails keeps its
old text, and the script exits 1 after the others.

Tables (`--only`):

- `hold`: the event core against a bare `BinaryHeap`, 10^3 and 10^6 pending (`-p vitro
  --example hold`), the ratio per CPU second of each run;
- `counts`: the same, counted under cachegrind (`scripts/hold_counts.py`; needs valgrind);
- `scale`: cost per event against the number of entities (`-p vitro-evac --example
  scale_table`), medians of several runs;
- `big`: the 10,000-entity rows of the same program, at the discrete and interpolated levels;
- `abm`: Flocking, Schelling and WolfSheep, Vitro against krABMaga (`scripts/abm_compare.sh`);
- `los`: line of sight, BVH against brute force (`-p vitro-site --example los_bench`);
- `levels`: simulated seconds per wall second at each level of fidelity (`-p vitro-behaviour
  --example level_speed`).
"""

import argparse
import os
import pathlib
import platform
import re
import statistics
import subprocess
import sys

import markers

ROOT = pathlib.Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "benchmarks.md"
TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
if not TARGET.is_absolute():
    TARGET = ROOT / TARGET
EXAMPLES = TARGET / "release" / "examples"


class Failed(Exception):
    """A benchmark program failed or printed something this script cannot read."""


# ---------------------------------------------------------------------------------------
# Running things


def log(msg):
    print(f"benchmarks: {msg}", file=sys.stderr, flush=True)


def build(crate, example):
    """Builds one example in release; returns its path."""
    log(f"building {crate} example {example} (release)")
    r = subprocess.run(
        ["cargo", "build", "--release", "--quiet", "-p", crate, "--example", example],
        cwd=ROOT,
    )
    if r.returncode != 0:
        raise Failed(f"cargo build --release -p {crate} --example {example} failed")
    path = EXAMPLES / example
    if not path.is_file():
        raise Failed(f"{path} was not built")
    return path


def run(cmd, what=None):
    """Runs `cmd` from the repository root; returns its stdout (stderr passes through)."""
    log(f"running {what or ' '.join(map(str, cmd))}")
    r = subprocess.run([str(c) for c in cmd], cwd=ROOT, stdout=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise Failed(f"`{' '.join(map(str, cmd))}` exited with {r.returncode}")
    return r.stdout


def machine():
    """One line about the machine the figures come from."""
    model = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = f", {int(line.split()[1]) / 2**20:.0f} GiB"
                break
    except OSError:
        pass
    load = ""
    try:
        load = f", load average {os.getloadavg()[0]:.1f} at the start"
    except OSError:
        pass
    rustc = subprocess.run(["rustc", "--version"], capture_output=True, text=True).stdout.split()
    rust = f", {rustc[0]} {rustc[1]}" if len(rustc) >= 2 else ""
    return f"{model}, {os.cpu_count()} CPUs{mem}, {platform.system()} {platform.release()}{rust}{load}"


def median_range(xs, fmt):
    xs = sorted(xs)
    m = statistics.median(xs)
    if len(xs) == 1:
        return fmt.format(m)
    return f"{fmt.format(m)} ({fmt.format(xs[0])}–{fmt.format(xs[-1])})"


def grab(pattern, text, what):
    m = re.search(pattern, text, re.M)
    if not m:
        raise Failed(f"no {what} in the output:\n{text}")
    return m


# ---------------------------------------------------------------------------------------
# The tables. Each returns the markdown between its markers.


def header(ctx, commands, note=""):
    lines = []
    if ctx.quick:
        lines.append("**Quick mode (tiny sizes): these rows check the script; they are not figures.**")
        lines.append("")
    lines.append(f"Machine: {ctx.machine}.{(' ' + note) if note else ''}")
    lines.append("")
    lines.append("```sh")
    lines.extend(commands)
    lines.append("```")
    lines.append("")
    return lines


def table_hold(ctx):
    hold = build("vitro", "hold")
    runs = 1 if ctx.quick else ctx.runs(5)
    cases = (
        [(1000, 200_000, 50_000, runs), (100_000, 200_000, 100_000, 1)]
        if ctx.quick
        else [(1000, 4_000_000, 100_000, runs), (1_000_000, 3_000_000, 300_000, 1)]
    )
    commands = ["cargo build --release -p vitro --example hold"]
    rows = []
    for pending, events, slice_, n in cases:
        cmd = [hold, pending, events, "--slice", slice_]
        commands.append(
            f"target/release/examples/hold {pending} {events} --slice {slice_}"
            + (f"   # {n} runs" if n > 1 else "")
        )
        got = []
        for _ in range(n):
            out = run(cmd)
            m = grab(
                r"^per CPU second: events/s (\d+), floor (\d+), bare queue (\d+), ratio ([\d.]+)",
                out,
                "per-CPU-second line",
            )
            s = grab(r"median of (\d+) slices: ([\d.]+)", out, "slice median")
            rss = re.search(r"^peak RSS MiB: ([\d.]+)", out, re.M)
            got.append(
                {
                    "sim": int(m[1]),
                    "floor": int(m[2]),
                    "queue": int(m[3]),
                    "ratio": float(m[4]),
                    "slices": float(s[2]),
                    "rss": float(rss[1]) if rss else None,
                }
            )
        rows.append((pending, events, got))
    lines = header(
        ctx,
        commands,
        "Each run fires the events three ways in turn, a slice at a time; the ratios are per CPU "
        "second of the run's thread, above 1 where the simulation is faster than the floor.",
    )
    lines.append(
        "| pending | runs | simulation, M events per CPU s | `BinaryHeap` floor | bare `EventQueue` "
        "| simulation / floor, each run | median | bare queue / floor |"
    )
    lines.append("|---:|---:|---:|---:|---:|---|---:|---:|")
    for pending, events, got in rows:
        med = lambda k: statistics.median(g[k] for g in got)
        each = ", ".join(f"{g['ratio']:.2f}" for g in got)
        lines.append(
            f"| {pending:,} | {len(got)} | {med('sim') / 1e6:.2f} | {med('floor') / 1e6:.2f} "
            f"| {med('queue') / 1e6:.2f} | {each} | **{med('ratio'):.2f}** "
            f"| {statistics.median(g['queue'] / g['floor'] for g in got):.2f} |"
        )
    return lines


def table_counts(ctx):
    hold = build("vitro", "hold")
    events = 20_000 if ctx.quick else 200_000
    cmd = [sys.executable, ROOT / "scripts" / "hold_counts.py", "--events", events, hold]
    out = run(cmd)
    rows = []
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 6 and f[-5] in ("simulation", "floor", "queue"):
            rows.append((f[-5], *map(float, f[-4:])))
    if len(rows) != 3:
        raise Failed(f"hold_counts.py printed {len(rows)} parts, not 3:\n{out}")
    lines = header(
        ctx,
        [
            "cargo build --release -p vitro --example hold",
            f"python3 scripts/hold_counts.py --events {events} target/release/examples/hold",
        ],
        "Counted under cachegrind, with a 32 KiB first-level and a 512 KiB second-level cache (deterministic: the load does not "
        "move it); per event in steady state, 10³ pending.",
    )
    names = {"simulation": "simulation (driver, trace, dispatch, queue)",
             "queue": "bare `EventQueue`", "floor": "`BinaryHeap` floor"}
    lines.append("| part | instructions | L1 data misses | L2 misses | mispredicted branches |")
    lines.append("|---|---:|---:|---:|---:|")
    for part, ins, l1, l2, mis in sorted(rows, key=lambda r: ["simulation", "queue", "floor"].index(r[0])):
        lines.append(f"| {names[part]} | {ins:.1f} | {l1:.2f} | {l2:.3f} | {mis:.2f} |")
    by = {r[0]: r for r in rows}
    sim, queue, floor = by["simulation"], by["queue"], by["floor"]
    lines.append("")
    lines.append(
        f"Side by side: the bare queue executes {queue[1] / floor[1]:.2f}× the heap's instructions "
        f"and {queue[4] / floor[4]:.2f}× its mispredicted branches, with {queue[2] / floor[2]:.1f}× "
        f"its first-level misses; the driver adds {sim[1] - queue[1]:.0f} instructions an event "
        f"over the bare queue."
    )
    return lines


def scale_rows(out):
    """The rows of one `scale_table` run: level entities blocks events wall µs/ev sim/wall cpu
    cpu-µs/ev setup peak sim hash."""
    rows = []
    for line in out.splitlines()[1:]:
        f = line.split()
        if len(f) != 13:
            continue
        rows.append(
            {
                "level": f[0],
                "entities": int(f[1]),
                "events": int(f[3]),
                "sim_per_wall": float(f[6]),
                "cpu_us": float(f[8]),
                "rss": float(f[10]),
                "sim_s": float(f[11]),
                "hash": f[12],
            }
        )
    if not rows:
        raise Failed(f"no rows in scale_table's output:\n{out}")
    return rows


def scale_lines(rows):
    groups = {}
    for r in rows:
        groups.setdefault((r["level"], r["entities"], r["sim_s"]), []).append(r)
    lines = [
        "| entities, level (simulated s) | runs | events | CPU µs per event, median (range) "
        "| sim s per wall s, median (range) | peak RSS MiB | trace hash |",
        "|---|---:|---:|---:|---:|---:|---|",
    ]
    medians = []
    for (level, n, sim_s), g in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        events = sorted({r["events"] for r in g})
        hashes = sorted({r["hash"] for r in g})
        medians.append((level, n, statistics.median(r["cpu_us"] for r in g)))
        lines.append(
            f"| {n:,}, {level} ({sim_s:.0f}) | {len(g)} | {'/'.join(f'{e:,}' for e in events)} "
            f"| {median_range([r['cpu_us'] for r in g], '{:.2f}')} "
            f"| {median_range([r['sim_per_wall'] for r in g], '{:,.0f}')} "
            f"| {statistics.median(r['rss'] for r in g):.0f} "
            f"| {'`' + hashes[0] + '`' if len(hashes) == 1 else 'differ: ' + ', '.join(hashes)} |"
        )
    return lines, medians


def table_scale(ctx):
    exe = build("vitro-evac", "scale_table")
    runs = 1 if ctx.quick else ctx.runs(9)
    args = ["--sizes", "150,500", "--until", "30"] if ctx.quick else ["--sizes", "150,500,2000", "--until", "600"]
    rows = []
    for i in range(runs):
        rows += scale_rows(run([exe, *args], f"scale_table {' '.join(args)} (run {i + 1} of {runs})"))
    lines = header(
        ctx,
        [
            "cargo build --release -p vitro-evac --example scale_table",
            f"target/release/examples/scale_table {' '.join(args)}"
            + (f"   # {runs} runs, one after the other" if runs > 1 else ""),
        ],
        "Each row runs in a process of its own; CPU time is the run's thread's, set-up excluded.",
    )
    table, medians = scale_lines(rows)
    lines += table
    for level in sorted({m[0] for m in medians}):
        ms = sorted((n, c) for lv, n, c in medians if lv == level)
        if len(ms) >= 2:
            (n0, c0), (n1, c1) = ms[0], ms[-1]
            lines.append("")
            lines.append(
                f"From {n0:,} to {n1:,} entities ({level}) the CPU cost of an event grows "
                f"**{c1 / c0:.2f}×** (medians, measured side by side in the same runs)."
            )
    return lines


def table_big(ctx):
    exe = build("vitro-evac", "scale_table")
    if ctx.quick:
        cases = [("discrete", ["--sizes", "1000", "--levels", "discrete", "--big", "500", "--until-big", "10"]),
                 ("interpolated", ["--sizes", "1000", "--levels", "interpolated", "--big", "500", "--until-big", "5"])]
    else:
        cases = [("discrete", ["--sizes", "10000", "--levels", "discrete", "--until-big", "600"]),
                 ("interpolated", ["--sizes", "10000", "--levels", "interpolated", "--until-big", "30"])]
    rows = []
    commands = ["cargo build --release -p vitro-evac --example scale_table"]
    for _, args in cases:
        rows += scale_rows(run([exe, *args]))
        commands.append(f"target/release/examples/scale_table {' '.join(args)}")
    lines = header(ctx, commands, "One run each.")
    table, _ = scale_lines(rows)
    return lines + table


ABM_CASES = ["flocking-small", "flocking-large", "schelling-small", "schelling-large",
             "wolfsheep-small", "wolfsheep-large"]


def table_abm(ctx):
    runs = 3 if ctx.quick else ctx.runs(100)
    cases = ["flocking-small", "schelling-small", "wolfsheep-small"] if ctx.quick else ABM_CASES
    args = [str(runs)] + (cases if ctx.quick else [])
    out = run(["bash", ROOT / "scripts" / "abm_compare.sh", *args])
    rows = []
    for line in out.splitlines()[1:]:
        if "|" not in line:
            continue
        left, kstats = line.split("|", 1)
        f = left.split()
        if len(f) < 8:
            continue
        model, size = f[0], f[1]
        vms, kms, ratio, vcpu, kcpu, cratio = map(float, f[2:8])
        vstats = " ".join(f[8:])
        rows.append((model, size, vms, kms, ratio, vcpu, kcpu, cratio, vstats, kstats.strip()))
    if not rows:
        raise Failed(f"no rows in abm_compare.sh's output:\n{out}")

    def stats(v, k):
        a, b = v.split(), k.split()
        da, db = dict(zip(a[::2], a[1::2])), dict(zip(b[::2], b[1::2]))
        return ", ".join(f"{key.replace('_', ' ')} {da[key]} / {db.get(key, '?')}" for key in a[::2])

    lines = header(
        ctx,
        [f"scripts/abm_compare.sh {' '.join(args)}"],
        f"Medians of {runs} runs (seeds 1–{runs}) of each model and size, each timed from building "
        "the model to its last step; both binaries run in turn on the same machine.",
    )
    names = {"flocking": "Flocking", "schelling": "Schelling", "wolfsheep": "WolfSheep"}
    lines.append(
        "| model | size | Vitro, CPU ms | krABMaga, CPU ms | ratio, CPU | ratio, wall "
        "| statistics, Vitro / krABMaga |"
    )
    lines.append("|---|---|---:|---:|---:|---:|---|")
    for model, size, vms, kms, ratio, vcpu, kcpu, cratio, vs, ks in rows:
        lines.append(
            f"| {names.get(model, model)} | {size} | {vcpu:.2f} | {kcpu:.2f} | **{cratio:.2f}** "
            f"| {ratio:.2f} | {stats(vs, ks)} |"
        )
    lines.append("")
    lines.append("ratio = Vitro / krABMaga (below 1: Vitro is faster).")
    return lines


def table_los(ctx):
    exe = build("vitro-site", "los_bench")
    pairs = 2_000 if ctx.quick else 200_000
    out = run([exe, pairs])
    scene = grab(r"^scene: (\d+) triangles \((\d+) ground", out, "scene line")
    sight = grab(r"^(\d+) pairs .*?([\d.]+) % in sight", out, "pairs line")
    bvh = grab(r"^BVH:\s+(\d+) queries/s \(([\d.]+) µs", out, "BVH line")
    brute = grab(r"^brute force:\s+(\d+) queries/s \(([\d.]+) µs each, (\d+) pairs", out, "brute-force line")
    speed = grab(r"^speed-up BVH / brute force: (\d+)x", out, "speed-up line")
    lines = header(
        ctx,
        ["cargo build --release -p vitro-site --example los_bench", f"target/release/examples/los_bench {pairs}"],
        "Random pairs of street points 2 m above the ground in Kotka on its terrain; the brute "
        "force checks a subset, and the answers must agree.",
    )
    lines.append("| method | pairs | queries per s | µs per query |")
    lines.append("|---|---:|---:|---:|")
    lines.append(f"| BVH | {int(sight[1]):,} | {int(bvh[1]):,} | {float(bvh[2]):.2f} |")
    lines.append(f"| every triangle | {int(brute[3]):,} | {int(brute[1]):,} | {float(brute[2]):.0f} |")
    lines.append("")
    lines.append(
        f"{int(scene[1]):,} triangles ({int(scene[2]):,} of them ground), {float(sight[2]):.1f} % of the "
        f"pairs in sight; the BVH answers **{int(speed[1]):,}×** as many queries a second."
    )
    return lines


def table_levels(ctx):
    exe = build("vitro-behaviour", "level_speed")
    secs = 20 if ctx.quick else 600
    out = run([exe, secs])
    rows = []
    for line in out.splitlines():
        m = re.match(r"^(\S.*?)\s+(\d+)\s+(\d+)\s+([\d.]+)\s+(\d+)$", line)
        if m and m[1] != "scene":
            rows.append((m[1], int(m[2]), int(m[3]), float(m[4]), int(m[5])))
    if not rows:
        raise Failed(f"no rows in level_speed's output:\n{out}")
    lines = header(
        ctx,
        ["cargo build --release -p vitro-behaviour --example level_speed",
         f"target/release/examples/level_speed {secs}"],
        f"{secs} simulated seconds per scene on Kotka; one run each.",
    )
    lines.append("| scene | entities | events | wall s | sim s per wall s |")
    lines.append("|---|---:|---:|---:|---:|")
    for name, n, ev, wall, speed in rows:
        lines.append(f"| {name} | {n} | {ev:,} | {wall:.3f} | {speed:,} |")
    by = {r[0]: r[4] for r in rows}
    pairs = [("all discrete", "all continuous"), ("20 vehicles, discrete", "20 vehicles, physical")]
    said = [f"{a} runs {by[a] / by[b]:,.0f}× as fast as {b}" for a, b in pairs if a in by and by.get(b)]
    if said:
        lines.append("")
        lines.append("Side by side: " + "; ".join(said) + ".")
    return lines


TABLES = {
    "hold": table_hold,
    "counts": table_counts,
    "scale": table_scale,
    "big": table_big,
    "abm": table_abm,
    "los": table_los,
    "levels": table_levels,
}


# ---------------------------------------------------------------------------------------
# The document


def replace(doc, path, name, body):
    try:
        return markers.replace(doc, "benchmarks.py", name, body, where=str(path))
    except markers.MarkerError as e:
        raise Failed(str(e)) from e


class Context:
    def __init__(self, quick, runs):
        self.quick = quick
        self._runs = runs
        self.machine = machine()

    def runs(self, default):
        return self._runs or default


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", help="comma-separated tables: " + ",".join(TABLES))
    ap.add_argument("--quick", action="store_true", help="tiny sizes, one run: checks the script")
    ap.add_argument("--runs", type=int, help="runs of every repeated measurement (default: hold 5, scale 9, abm 100)")
    ap.add_argument("--out", type=pathlib.Path, default=DOC, help="the document to rewrite")
    ap.add_argument("--print", action="store_true", help="print the tables instead of writing them")
    ap.add_argument("--list", action="store_true", help="list the tables and exit")
    a = ap.parse_args()
    if a.list:
        for name, f in TABLES.items():
            print(f"{name:<8} {f.__name__}")
        return 0
    names = a.only.split(",") if a.only else list(TABLES)
    unknown = [n for n in names if n not in TABLES]
    if unknown:
        ap.error(f"unknown table(s) {', '.join(unknown)}; known: {', '.join(TABLES)}")
    path = a.out
    ctx = Context(a.quick, a.runs)
    doc = path.read_text()
    try:  # every marker present before anything runs
        for name in names:
            replace(doc, path, name, [])
    except Failed as e:
        log(str(e))
        return 2
    failed = []
    for name in names:
        try:
            body = TABLES[name](ctx)
        except Failed as e:
            log(f"{name}: {e}")
            failed.append(name)
            continue
        if a.print:
            print("\n".join(body) + "\n")
        else:
            doc = replace(doc, path, name, body)
            path.write_text(doc)
            log(f"{name}: written to {path}")
    if failed:
        log(f"failed, left as they were: {', '.join(failed)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
