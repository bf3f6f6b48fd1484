#!/usr/bin/env python3
"""The calibration page's tables, from a calibration file (`vitro calibrate --out FILE`) or from
the `start_turns` example's output.

    python3 scripts/calibration_table.py ground FILE      # the vehicles' trip fits
    python3 scripts/calibration_table.py aircraft FILE    # the aircraft's flight fits
    target/release/examples/start_turns FILE cargo_truck 8 \\
        | python3 scripts/calibration_table.py start-turns
    target/release/vitro check levels --calibration FILE --json \\
        | python3 scripts/calibration_table.py predicts

`ground`: one row per vehicle fit (entity types whose concrete level is `physical`; the
troopers' fits, against the directed level, are left out): the six parameters, the number of
trips the outlier screen left out (in brackets after the entity, where any), and the bias and
MAPE before and after calibration on the fitted and the held-out trips (% of the concrete
time; held out: with the largest error). `aircraft`: the same per aircraft type, five
parameters. `start-turns`: the example's rows (start turn, physical extra time mean [min,
max], interpolated, trips) turned into the page's table, one column per angle above 0.
`predicts`: the rows of the property "the abstract level predicts the concrete one" from
`vitro check levels --json`, one per entity type and abstract level.
Prints the table only. Standard library only (tomllib: Python 3.11).
"""

import json
import sys
import tomllib


def signed(x, digits=1):
    return f"{x:+.{digits}f}".replace("-", "−")


def plain(x, digits):
    s = f"{x:.{digits}f}"
    return s.replace("-", "−") if float(s) != 0 else s.lstrip("-")


def residuals(fit, held):
    f, h = fit, held
    return (
        f"{signed(f['bias_pct_before'])} → {signed(f['bias_pct_after'])} "
        f"({f['mape_pct_before']:.1f} → {f['mape_pct_after']:.1f})",
        f"{signed(h['bias_pct_before'])} → {signed(h['bias_pct_after'])} "
        f"({h['mape_pct_before']:.1f} → {h['mape_pct_after']:.1f}, max {h['max_pct_after']:.1f})",
    )


def ground(cal):
    print("| entity (left out by the screen) | level | alpha | beta s | kappa s/rad | gamma s/m "
          "| delta s/rad | epsilon s/rad² | fitted: bias before → after (MAPE) "
          "| held out: bias before → after (MAPE, max) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for f in cal.get("fit", []):
        if f["concrete"] != "physical":
            continue
        who = f["entity"] + (f" ({f['excluded']})" if f.get("excluded") else "")
        eps = "0 (left out)" if f["epsilon"] == 0 else plain(f["epsilon"], 2)
        fitted, held = residuals(f["fit_residuals"], f["held_out"])
        print(f"| {who} | {f['level']} | {plain(f['alpha'], 3)} | {plain(f['beta'], 1)} "
              f"| {plain(f['kappa'], 2)} | {plain(f['gamma'], 3)} | {plain(f['delta'], 2)} "
              f"| {eps} | {fitted} | {held} |")


def aircraft(cal):
    print("| aircraft | lattice vs | alpha | beta s | kappa s/rad | gamma s/m | delta s/rad "
          "| fitted: bias % before → after (MAPE) | held out: bias % before → after (MAPE, max) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for f in cal.get("aircraft", []):
        fitted, held = residuals(f["fit_residuals"], f["held_out"])
        print(f"| {f['entity'].capitalize()} | {f['concrete']} | {plain(f['alpha'], 3)} "
              f"| {plain(f['beta'], 1)} | {plain(f['kappa'], 2)} | {plain(f['gamma'], 3)} "
              f"| {plain(f['delta'], 2)} | {fitted} | {held} |")


def start_turns(text):
    cols = []
    for line in text.splitlines():
        parts = [p.strip() for p in line.split("|")]
        if len(parts) != 4 or not parts[0].replace(".", "").isdigit():
            continue
        deg = float(parts[0])
        mean, rng = parts[1].split("[")
        lo, hi = rng.rstrip("]").split(",")
        if deg > 0:
            cols.append((deg, float(mean), float(lo), float(hi), int(parts[3])))
    if not cols:
        sys.exit("no rows in the start_turns output")
    starts = sorted({c[4] for c in cols})
    print("| start turn | " + " | ".join(f"{d:.0f}°" for d, *_ in cols) + " |")
    print("|---|" + "---|" * len(cols))
    print(f"| extra time, s, mean over {'/'.join(map(str, starts))} starts | "
          + " | ".join(plain(m, 1) for _, m, *_ in cols) + " |")
    print("| range, s | " + " | ".join(f"{plain(lo, 1)} – {plain(hi, 1)}" for _, _, lo, hi, _ in cols)
          + " |")


def predicts(text):
    rows = [r for r in json.loads(text) if r["property"].startswith("predicts ")]
    if not rows:
        sys.exit("no `predicts` rows: was --calibration given?")
    print("| entity | level | against | holds | mean abs error, % | limit (before calibration) |")
    print("|---|---|---|---|---:|---|")
    for r in rows:
        limit = r["limit"].replace("|", "\\|")  # a pipe in a cell ends it
        print(f"| {r['entity']} | {r['level']} | {r['property'].split(' ', 1)[1]} "
              f"| {'yes' if r['pass'] else 'no'} | {r['value']:.2f} | {limit} |")


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("start-turns", "predicts"):
        return (start_turns if sys.argv[1] == "start-turns" else predicts)(sys.stdin.read())
    if len(sys.argv) != 3 or sys.argv[1] not in ("ground", "aircraft"):
        sys.exit(__doc__)
    with open(sys.argv[2], "rb") as f:
        cal = tomllib.load(f)
    (ground if sys.argv[1] == "ground" else aircraft)(cal)


if __name__ == "__main__":
    main()
