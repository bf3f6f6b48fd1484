#!/usr/bin/env python3
"""Summarises runs of experiments/mission_patrol.toml: per look-ahead of the patrol game
(patrol.horizon), the attacks the game's attacker started, the mean capture probability the
solved game computes for the attacks chosen, and the realised stop rate with its Wilson 95 %
interval; for all attacks and for those through which the patrol kept its schedule (where the
game's assumptions held). Also the calibration by computed probability (rounded to 0.05).

A computed probability within the realised rate's interval agrees with it. (Each run has one
attack, so the attacks are independent; the computed mean is itself a mean of fixed
numbers, the game's exact probabilities of the states chosen.)

Usage: python3 scripts/patrol_table.py [--markdown] RESULTS_DIR

With --markdown, prints only the guide's table (per look-ahead, largest first: all attacks, on
schedule, off schedule; a group without attacks left out) and one line per look-ahead under
it: the runs, the attacks on a misread state, the runs that re-solved, and the game's least
capture probability.
"""

import csv
import math
import pathlib
import sys

from table_stats import wilson, num


def line(label: str, attacks: list[tuple[float, bool]]) -> str:
    n = len(attacks)
    k = sum(1 for _, s in attacks if s)
    computed = sum(p for p, _ in attacks) / n if n else math.nan
    lo, hi = wilson(k, n)
    rate = k / n if n else math.nan
    agree = "yes" if lo - 1e-9 <= computed <= hi + 1e-9 else "NO"
    return (f"{label:<28} {n:>5} {computed:>9.3f} {rate:>9.3f}  [{lo:.3f}, {hi:.3f}]  {agree}")


def markdown_row(label: str, attacks: list[tuple[float, bool]]) -> str:
    n = len(attacks)
    k = sum(1 for _, s in attacks if s)
    computed = sum(p for p, _ in attacks) / n
    lo, hi = wilson(k, n)
    agree = "yes" if lo - 1e-9 <= computed <= hi + 1e-9 else "no"
    return f"| {label} | {n} | {computed:.3f} | {k / n:.3f} [{lo:.3f}, {hi:.3f}] | {agree} |"


def markdown(groups: dict) -> None:
    print("| look-ahead | attacks | computed | realised stop rate | agrees |")
    print("|---|---:|---:|---|---|")
    notes = []
    for h in sorted(groups, reverse=True):
        rs = groups[h]
        every, on = attacks(rs)
        misread = sum(1 for r in rs if num(r.get("patrol_attacks_misread")) >= 1)
        resolved = sum(1 for r in rs if num(r.get("patrol_resolves")) >= 1)
        game = min(num(r["patrol_capture_probability"]) for r in rs)
        for label, group in (("all attacks", every), ("on schedule", on),
                             ("off schedule", off_schedule(rs))):
            if group:
                print(markdown_row(f"{h}, {label}", group))
        notes.append(f"- Look-ahead {h}: {len(rs)} runs, {len(every)} attacks, {misread} of them on "
                     f"a misread state; {resolved} runs re-solved the game; the game's least "
                     f"capture probability {game:.3f}.")
    print()
    print("\n".join(notes))


def attacks(rs: list) -> tuple[list, list]:
    every, on = [], []
    for r in rs:
        if num(r["patrol_attacks"]) >= 1:
            every.append((num(r["patrol_capture_computed"]), num(r["patrol_attacks_stopped"]) >= 1))
        if num(r["patrol_attacks_on_schedule"]) >= 1:
            on.append((num(r["patrol_capture_on_schedule"]), num(r["patrol_stopped_on_schedule"]) >= 1))
    return every, on


def main() -> None:
    args = sys.argv[1:]
    md = "--markdown" in args
    args = [a for a in args if a != "--markdown"]
    if len(args) != 1:
        sys.exit(__doc__)
    rows = list(csv.DictReader(open(pathlib.Path(args[0]) / "summary.csv")))
    groups: dict = {}
    for r in rows:
        groups.setdefault(r.get("patrol.horizon", "-"), []).append(r)
    if md:
        return markdown(groups)
    print(f"{'horizon / attacks':<28} {'n':>5} {'computed':>9} {'realised':>9}  Wilson 95 %        agree")
    for h in sorted(groups):
        rs = groups[h]
        every, on = attacks(rs)
        game = min(num(r["patrol_capture_probability"]) for r in rs)
        misread = sum(1 for r in rs if num(r.get("patrol_attacks_misread")) >= 1)
        print(f"horizon {h}: {len(rs)} runs, {len(every)} attacks ({misread} on a misread state); "
              f"the game's least capture probability {game:.3f}")
        print(line("  all attacks", every))
        print(line("  patrol on schedule", on))
        print(line("  patrol off schedule", off_schedule(rs)))
        bins: dict = {}
        for p, s in on:
            bins.setdefault(round(p * 20) / 20, []).append((p, s))
        for b in sorted(bins):
            print(line(f"    on schedule, p ~ {b:.2f}", bins[b]))


def off_schedule(rs: list) -> list:
    out = []
    for r in rs:
        if num(r["patrol_attacks"]) >= 1 and num(r["patrol_attacks_on_schedule"]) < 1:
            out.append((num(r["patrol_capture_computed"]), num(r["patrol_attacks_stopped"]) >= 1))
    return out


if __name__ == "__main__":
    main()
