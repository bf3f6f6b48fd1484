#!/usr/bin/env bash
# The ABM frameworks comparison's models on Vitro and on krABMaga 0.6, side by side.
#
#   scripts/abm_compare.sh [RUNS] [MODEL-SIZE ...]
#
# Builds, in release, Vitro's `abm_bench` example (crates/vitro-abm) and the krABMaga peer
# (bench/krabmaga-abm, outside the workspace: its own Cargo.lock, built only here), runs
# each model and size RUNS times (default 100, seeds 1..RUNS; each run timed from building
# the model to its last step) and prints one line per model and size:
#
#   model size vitro_ms krabmaga_ms ratio vitro_cpu krabmaga_cpu cpu_ratio | statistics
#
# ratio = Vitro median wall time / krABMaga median wall time (below 1: Vitro is faster);
# the cpu columns are the medians of the thread's CPU time (steadier on a loaded machine,
# where wall time counts the waits for a core). The statistics are
# medians over the runs (Schelling: share of happy households; Flocking: polarisation and
# mean neighbour count; WolfSheep: sheep and wolves after 100 steps and the sheep peak), to
# check that both implement the same model. MODEL-SIZE: flocking-small, flocking-large,
# schelling-small, schelling-large, wolfsheep-small, wolfsheep-large (default: all).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
runs="${1:-100}"
shift || true
cases=("$@")
if [ ${#cases[@]} -eq 0 ]; then
    cases=(flocking-small flocking-large schelling-small schelling-large wolfsheep-small wolfsheep-large)
fi
target="${CARGO_TARGET_DIR:-$root/target}"

echo "building Vitro's abm_bench (release)..." >&2
cargo build --release --quiet --manifest-path "$root/Cargo.toml" -p vitro-abm --example abm_bench
echo "building the krABMaga peer (release)..." >&2
CARGO_TARGET_DIR="$target/krabmaga-abm" cargo build --release --quiet \
    --manifest-path "$root/bench/krabmaga-abm/Cargo.toml"

vitro_bin="$target/release/examples/abm_bench"
krab_bin="$target/krabmaga-abm/release/krabmaga-abm"

printf '%-10s %-6s %10s %12s %6s %10s %12s %9s  %s\n' model size vitro_ms krabmaga_ms ratio \
    vitro_cpu krabmaga_cpu cpu_ratio "statistics (vitro | krabmaga)"
for c in "${cases[@]}"; do
    v="$("$vitro_bin" "$runs" "$c")"
    k="$("$krab_bin" "$runs" "$c")"
    # Lines: "<framework> <model> <size> median_ms <ms> cpu_ms <ms> <stat> <value> ..."
    read -r _ model size _ vms _ vcpu vstats <<<"$v"
    read -r _ _ _ _ kms _ kcpu kstats <<<"$k"
    ratio="$(awk -v a="$vms" -v b="$kms" 'BEGIN { printf "%.2f", a / b }')"
    cratio="$(awk -v a="$vcpu" -v b="$kcpu" 'BEGIN { printf "%.2f", a / b }')"
    printf '%-10s %-6s %10s %12s %6s %10s %12s %9s  %s | %s\n' "$model" "$size" "$vms" "$kms" \
        "$ratio" "$vcpu" "$kcpu" "$cratio" "$vstats" "$kstats"
done
