#!/usr/bin/env python3
"""Reruns the measurements behind the documentation's tables and rewrites each table in place.

    python3 scripts/doc_tables.py --list                    # the tables, their pages and commands
    python3 scripts/doc_tables.py --check                   # markers and commands only; runs nothing
    python3 scripts/doc_tables.py --cheap                   # the tables that take a few minutes
    python3 scripts/doc_tables.py --only patrol,repair      # some tables
    python3 scripts/doc_tables.py                           # every table (about an hour on 2 cores)

Options: `--jobs N` (runs at once, default 2; the results do not depend on it), `--seeds N`
(the tables whose command takes a seed count; the page then states N), `--vitro PATH` (the
`vitro` binary; default `$VITRO_BIN`, else `target/release/vitro`, built if missing),
`--target DIR` (where the binaries are built; default `$CARGO_TARGET_DIR`, else `target`),
`--no-build` (build nothing: use the binaries that are there), `--reuse` (a step whose output
is already there, a batch's result directory, a calibration file or the fidelity CSVs, is not
run again: only the table script runs), `--print` (print the blocks instead of writing them).

Each table sits in its page between two markers,

    <!-- doc_tables.py: NAME -->
    ...
    <!-- /doc_tables.py: NAME -->

and is replaced as a whole by the commands that made it (a `sh` block, as run from the
repository root, with the binary shown as `target/release/vitro`) and what the last of them
printed: a Markdown table, or the program's output in a `text` block. Text outside the markers
is left alone. A batch's result directory (under `results/`) is removed before the batch runs.
The examples are built first (`cargo build --release -p CRATE --example NAME`). A table whose
commands fail keeps its old text; the script exits 1 after the others. `--check` verifies that
every registered table has its markers in its page, that every marker in the documentation has
an entry here, and that the command block inside each pair is the one this script would run.
"""

import argparse
import os
import pathlib
import re
import shlex
import shutil
import string
import subprocess
import sys

import markers

ROOT = pathlib.Path(__file__).resolve().parent.parent
TOOL = "doc_tables.py"
SHOWN_VITRO = "target/release/vitro"
SHOWN_EXAMPLES = "target/release/examples"
CALIBRATE = (
    "{vitro} calibrate scenarios/evacuation.toml --from physical --to discrete,interpolated "
    "--out scenarios/calibration/evacuation.toml --trips 48 --held-out 24 --flights 24 "
    "--held-out-flights 12 --jobs {jobs} --plot docs/calibration"
)
CALIBRATION = "scenarios/calibration/evacuation.toml"


class Table:
    """One measured table: its page, the commands that make it (the last prints it), what it
    builds first, the path a step makes (removed first under results/, kept by --reuse), its
    default seed count (for `{seeds}`), about how many minutes it takes on 2 cores, whether
    its output is shown as text rather than as a Markdown table, and the exit codes that are
    results rather than failures (`vitro check` exits 4 when a property fails: the table
    then shows the failing rows)."""

    def __init__(self, page, commands, builds=(), makes=None, seeds=None, minutes=1, text=False,
                 ok_codes=(0,)):
        self.page, self.commands, self.builds = page, commands, builds
        self.makes, self.seeds, self.minutes, self.text = makes or {}, seeds, minutes, text
        self.ok_codes = ok_codes


def batch(experiment, out, script):
    return [f"{{vitro}} batch experiments/{experiment}.toml --out {out} --jobs {{jobs}}", script]


ALGORITHMS = "docs/guide/src/algorithms.md"
CAL_PAGE = "docs/guide/src/calibration.md"
TABLES = {
    "readme_run": Table("README.md", ["{vitro} run scenarios/evacuation.toml"], text=True),
    "patrol": Table(
        ALGORITHMS,
        batch("mission_patrol", "results/mission_patrol",
              "python3 scripts/patrol_table.py --markdown results/mission_patrol"),
        makes={0: "results/mission_patrol"}, minutes=2),
    "hunt": Table(
        ALGORITHMS,
        batch("mission_hunt", "results/mission_hunt",
              "python3 scripts/hunt_table.py --batch results/mission_hunt"),
        makes={0: "results/mission_hunt"}, minutes=20),
    "repair": Table(
        "docs/repair.md",
        batch("mission_repair", "results/mission_repair",
              "python3 scripts/repair_table.py results/mission_repair"),
        makes={0: "results/mission_repair"}, minutes=5),
    "repair_depth": Table(
        "docs/repair.md",
        batch("mission_repair_depth", "results/mission_repair_depth",
              "python3 scripts/repair_table.py results/mission_repair_depth"),
        makes={0: "results/mission_repair_depth"}, minutes=2),
    "pursuit_mcts": Table(
        "docs/pursuit_game.md", ["scripts/pursuit_table.sh {vitro} mcts 300 20"], minutes=1),
    "pursuit_minimax": Table(
        "docs/pursuit_game.md", ["scripts/pursuit_table.sh {vitro} minimax 3000 20"], minutes=1),
    "pursuit_anytime": Table(
        "docs/pursuit_game.md", ["{examples}/pursuit_anytime"],
        builds=[("vitro-algo", "pursuit_anytime")], minutes=3, text=True),
    "start_turns": Table(
        CAL_PAGE,
        [f"{{examples}}/start_turns {CALIBRATION} cargo_truck 8 "
         "| python3 scripts/calibration_table.py start-turns"],
        builds=[("vitro-evac", "start_turns")], minutes=2),
    "calibration_aircraft": Table(
        CAL_PAGE, [CALIBRATE, f"python3 scripts/calibration_table.py aircraft {CALIBRATION}"],
        makes={0: CALIBRATION}, minutes=2),
    "calibration_ground": Table(
        CAL_PAGE, [CALIBRATE, f"python3 scripts/calibration_table.py ground {CALIBRATION}"],
        makes={0: CALIBRATION}, minutes=2),
    "check_levels": Table(
        CAL_PAGE,
        [f"{{vitro}} check levels --calibration {CALIBRATION} --json "
         "| python3 scripts/calibration_table.py predicts"],
        minutes=1, ok_codes=(0, 4)),
    "fidelity_30": Table(
        CAL_PAGE,
        ["python3 scripts/fidelity_table.py --binary {vitro} --seeds {seeds} --jobs {jobs} "
         f"--calibration {CALIBRATION} --uncalibrated-too"],
        seeds=30, minutes=3),
    "fidelity_100": Table(
        CAL_PAGE,
        ["python3 scripts/fidelity_table.py --binary {vitro} --seeds {seeds} --jobs {jobs} "
         "--out docs/fidelity.csv",
         "python3 scripts/fidelity_table.py --binary {vitro} --seeds {seeds} --jobs {jobs} "
         f"--levels discrete,interpolated --calibration {CALIBRATION} "
         "--out docs/fidelity_calibrated.csv",
         "python3 scripts/fidelity_table.py --read docs/fidelity.csv "
         "--read-calibrated docs/fidelity_calibrated.csv"],
        makes={0: "docs/fidelity.csv", 1: "docs/fidelity_calibrated.csv"}, seeds=100, minutes=9),
    "surveillance": Table(
        "experiments/README.md",
        batch("surveillance_uavs", "results/surveillance_uavs",
              "python3 scripts/surveillance_table.py results/surveillance_uavs/summary.csv"),
        makes={0: "results/surveillance_uavs"}, minutes=2),
    "allocation": Table(
        "experiments/README.md",
        batch("surveillance_allocation", "results/surveillance_allocation",
              "python3 scripts/allocation_table.py results/surveillance_allocation/summary.csv"),
        makes={0: "results/surveillance_allocation"}, minutes=2),
    "traffic": Table(
        "experiments/README.md",
        batch("traffic_levels", "results/traffic_levels",
              "python3 scripts/traffic_table.py results/traffic_levels/summary.csv"),
        makes={0: "results/traffic_levels"}, minutes=12),
}

# Pages --check scans for markers.
PAGES = ["README.md", "experiments/README.md", "docs"]


class Failed(Exception):
    """A command failed, or a page's markers are wrong."""


def log(msg):
    print(f"doc_tables: {msg}", file=sys.stderr, flush=True)


class Context:
    def __init__(self, a):
        target = pathlib.Path(a.target or os.environ.get("CARGO_TARGET_DIR") or "target")
        self.target = target if target.is_absolute() else ROOT / target
        self.examples = self.target / "release" / "examples"
        vitro = a.vitro or os.environ.get("VITRO_BIN")
        self.vitro_built_here = not vitro  # the default binary, built when it is missing
        self.vitro = pathlib.Path(vitro or self.target / "release" / "vitro").resolve()
        self.jobs, self.seeds, self.build, self.reuse = a.jobs, a.seeds, not a.no_build, a.reuse
        self.done = {}  # command -> stdout, so a step two tables share runs once

    def values(self, t, shown):
        return {
            "vitro": SHOWN_VITRO if shown else shlex.quote(str(self.vitro)),
            "examples": SHOWN_EXAMPLES if shown else shlex.quote(str(self.examples)),
            "jobs": self.jobs,
            "seeds": self.seeds or t.seeds,
        }


def shown_commands(t, ctx):
    lines = [f"cargo build --release -p {c} --example {e}" for c, e in t.builds]
    return lines + [c.format(**ctx.values(t, True)) for c in t.commands]


def block(t, ctx, out):
    lines = ["```sh", *shown_commands(t, ctx), "```", ""]
    out = out.rstrip("\n").split("\n")
    return lines + (["```text", *out, "```"] if t.text else out)


def build(crate, example, ctx):
    path = ctx.examples / example
    if not ctx.build:
        if not path.is_file():
            raise Failed(f"{path} is not built (--no-build)")
        return
    log(f"building {crate} example {example} (release)")
    env = dict(os.environ, CARGO_TARGET_DIR=str(ctx.target))
    cmd = ["cargo", "build", "--release", "--quiet", "-p", crate, "--example", example]
    if subprocess.run(cmd, cwd=ROOT, env=env).returncode != 0:
        raise Failed(f"cargo build --release -p {crate} --example {example} failed")


def run_table(name, ctx):
    t = TABLES[name]
    if not ctx.vitro.is_file() and ctx.vitro_built_here and ctx.build:
        log("building vitro-cli (release)")
        env = dict(os.environ, CARGO_TARGET_DIR=str(ctx.target))
        subprocess.run(["cargo", "build", "--release", "--quiet", "-p", "vitro-cli"], cwd=ROOT, env=env)
    if not ctx.vitro.is_file():
        raise Failed(f"no vitro binary at {ctx.vitro} (cargo build --release -p vitro-cli, or --vitro)")
    for crate, example in t.builds:
        build(crate, example, ctx)
    out = ""
    for i, template in enumerate(t.commands):
        cmd = template.format(**ctx.values(t, False))
        last = i == len(t.commands) - 1
        made = t.makes.get(i)
        if cmd in ctx.done:
            out = ctx.done[cmd]
            continue
        if made and ctx.reuse and (ROOT / made).exists():
            log(f"{name}: reusing {made}")
            continue
        if made and made.startswith("results/") and (ROOT / made).exists():
            shutil.rmtree(ROOT / made)
        log(f"{name}: running {cmd}")
        r = subprocess.run(["bash", "-o", "pipefail", "-c", cmd], cwd=ROOT,
                           stdout=subprocess.PIPE if last else sys.stderr, text=True)
        if r.returncode not in t.ok_codes:
            raise Failed(f"`{cmd}` exited with {r.returncode}")
        out = r.stdout if last else ""
        ctx.done[cmd] = out
    if not out.strip():
        raise Failed("the last command printed nothing")
    return block(t, ctx, out)


# ---------------------------------------------------------------------------------------
# The pages


def pages():
    for p in PAGES:
        path = ROOT / p
        yield from sorted(path.rglob("*.md")) if path.is_dir() else [path]


def pattern_of(template, t, ctx):
    """A regular expression of a command as shown, any count in place of {jobs} and {seeds}."""
    values = ctx.values(t, True)
    out = []
    for literal, field, _, _ in string.Formatter().parse(template):
        out.append(re.escape(literal))
        if field in ("jobs", "seeds"):
            out.append(r"\d+")
        elif field is not None:
            out.append(re.escape(str(values[field])))
    return "".join(out)


def check(ctx):
    """Problems with the markers and command blocks (an empty list when all is well)."""
    problems = []
    found = {}
    for path in pages():
        rel = str(path.relative_to(ROOT))
        if "/book/" in rel:
            continue
        doc = path.read_text()
        try:
            for name in markers.names(doc, TOOL, where=rel):
                found[name] = rel
        except markers.MarkerError as e:
            problems.append(str(e))
    for name, rel in found.items():
        if name not in TABLES:
            problems.append(f"{rel}: block `{name}` has no entry in {TOOL}")
    for name, t in TABLES.items():
        if found.get(name) != t.page:
            where = f"in {found[name]}" if name in found else "nowhere"
            problems.append(f"`{name}`: markers expected in {t.page}, found {where}")
            continue
        lines = markers.body((ROOT / t.page).read_text(), TOOL, name)
        want = shown_commands(t, ctx)
        got = lines[1:1 + len(want)] if lines and lines[0] == "```sh" else []
        pattern = [re.escape(w) for w in want[:len(t.builds)]] + [pattern_of(c, t, ctx) for c in t.commands]
        if len(got) != len(want) or not all(re.fullmatch(p, g) for p, g in zip(pattern, got)):
            problems.append(f"{t.page}: block `{name}` does not start with its commands:\n  "
                            + "\n  ".join(want))
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--list", action="store_true", help="list the tables and exit")
    ap.add_argument("--check", action="store_true", help="check markers and commands; run nothing")
    ap.add_argument("--only", help="comma-separated tables: " + ",".join(TABLES))
    ap.add_argument("--cheap", action="store_true", help="only the tables of at most 5 minutes")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once (default 2)")
    ap.add_argument("--seeds", type=int, help="seeds of the tables that take a seed count")
    ap.add_argument("--vitro", help="the vitro binary (default $VITRO_BIN or target/release/vitro)")
    ap.add_argument("--target", help="cargo target directory of the examples")
    ap.add_argument("--no-build", action="store_true", help="build no example; use those there")
    ap.add_argument("--reuse", action="store_true", help="keep result directories that exist")
    ap.add_argument("--print", action="store_true", help="print the blocks instead of writing them")
    a = ap.parse_args()
    ctx = Context(a)
    if a.list:
        for name, t in TABLES.items():
            print(f"{name}  ({t.page}, about {t.minutes} min on 2 cores)")
            for c in shown_commands(t, ctx):
                print(f"    {c}")
        return 0
    if a.check:
        problems = check(ctx)
        for p in problems:
            log(p)
        if not problems:
            log(f"{len(TABLES)} tables, each with its markers and commands")
        return 1 if problems else 0
    names = a.only.split(",") if a.only else list(TABLES)
    unknown = [n for n in names if n not in TABLES]
    if unknown:
        ap.error(f"unknown table(s) {', '.join(unknown)}; known: {', '.join(TABLES)}")
    if a.cheap:
        names = [n for n in names if TABLES[n].minutes <= 5]
    try:  # every marker present before anything runs
        for name in names:
            page = ROOT / TABLES[name].page
            markers.replace(page.read_text(), TOOL, name, [], where=str(page))
    except markers.MarkerError as e:
        log(str(e))
        return 2
    failed = []
    for name in names:
        try:
            body = run_table(name, ctx)
        except Failed as e:
            log(f"{name}: {e}")
            failed.append(name)
            continue
        if a.print:
            print("\n".join(body) + "\n")
        else:
            page = ROOT / TABLES[name].page
            page.write_text(markers.replace(page.read_text(), TOOL, name, body, where=str(page)))
            log(f"{name}: written to {TABLES[name].page}")
    if failed:
        log(f"failed, left as they were: {', '.join(failed)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
