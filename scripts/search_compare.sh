#!/usr/bin/env bash
# The measured claim of `vitro search`: with the same budget, how many failing runs (the VIP
# hit) does the adaptive strategy (cross-entropy method) find on experiments/mission_search.toml,
# against uniform random sampling, over several search seeds? Runs both strategies for each
# seed (no shrinking), then prints the table and draws docs/search_failures.png.
#
#   scripts/search_compare.sh [OUT]          # default OUT: results/search_compare
#   SEEDS="1 2 3" BUDGET=120 VITRO=path/to/vitro scripts/search_compare.sh
#
# An interrupted run picks up where it stopped (each search resumes from its journal).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
target="${CARGO_TARGET_DIR:-target}"
vitro="${VITRO:-$target/release/vitro}"
out="${1:-results/search_compare}"
seeds="${SEEDS:-1 2 3 4 5 6 7 8 9 10 11 12}"
budget="${BUDGET:-120}"
jobs="${JOBS:-2}"
[ -x "$vitro" ] || cargo build --release -p vitro-cli
mkdir -p "$out"
for s in $seeds; do
    for st in adaptive random; do
        d="$out/$st-$s"
        resume=()
        [ -e "$d/manifest.json" ] && resume=(--resume)
        printf '%s seed %s: ' "$st" "$s"
        "$vitro" search experiments/mission_search.toml --out "$d" --seed "$s" --strategy "$st" \
            --budget "$budget" --shrink 0 --jobs "$jobs" "${resume[@]}" 2>/dev/null
    done
done
dirs=()
for s in $seeds; do dirs+=("$out/adaptive-$s" "$out/random-$s"); done
cargo run --release -q -p vitro-cli --example search_compare -- "${dirs[@]}" --out docs/search_failures.png
rm -f docs/search_failures.svg   # the PNG is the one the guide shows (experiments.md)
