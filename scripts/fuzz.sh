#!/usr/bin/env bash
# Coverage-guided fuzzing of every parser of outside input (fuzz/, cargo fuzz + libFuzzer).
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]
#
# Builds the targets (stable toolchain: `--sanitizer none`), seeds a corpus per target in a
# temporary directory with the repository's own files and fixtures, runs each target for
# SECONDS (default 30) with a fixed seed, as many at once as there are cores (each target is
# one process on one core), and prints a table: executions, coverage (libFuzzer's `cov:`
# edges), crashes. Exits 1 if any target crashed; the crashing input is kept under $FUZZ_OUT
# (default: the temporary directory, printed) as crash-*.
#
# libFuzzer itself (C++, which libfuzzer-sys's build script would compile in every cold build)
# is compiled once per libfuzzer-sys version and profile and kept in a cache,
# $XDG_CACHE_HOME/vitro-libfuzzer-VERSION-PROFILE/libfuzzer.a; later builds link that archive
# (libfuzzer-sys's CUSTOM_LIBFUZZER_PATH).
#
# Environment:
#   FUZZ_FEATURES  target groups to build (fuzz/Cargo.toml): default all
#                  ("text site record missions"); "text" is the cheap subset.
#   FUZZ_PROFILE   "release" (default) or "dev" (cargo fuzz build --dev).
#   FUZZ_OUT       where corpora and crashes go (default: a new temporary directory).
#   FUZZ_BUILD     0: run the targets already built, without building.
#   FUZZ_JOBS      targets run at once (default: the number of cores).
#   FUZZ_CACHE     where the libFuzzer archive is kept (default $XDG_CACHE_HOME or ~/.cache);
#                  "none": libfuzzer-sys compiles it in every cold build.
#   CARGO_TARGET_DIR  default target/fuzz (kept apart from the main build).
set -euo pipefail

cd "$(dirname "$0")/.."
repo=$(pwd)
seconds=${1:-30}
shift || true
features=${FUZZ_FEATURES:-text site record missions}
profile=${FUZZ_PROFILE:-release}
# Absolute: the build runs in fuzz/, the targets are run from here.
CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$repo/target/fuzz}
case "$CARGO_TARGET_DIR" in /*) ;; *) CARGO_TARGET_DIR=$repo/$CARGO_TARGET_DIR ;; esac
export CARGO_TARGET_DIR
out=${FUZZ_OUT:-$(mktemp -d -t vitro-fuzz.XXXXXX)}
mkdir -p "$out"

# The targets each group holds (the bins of fuzz/Cargo.toml).
declare -A group=(
    [text]="pddl_domain pddl_problem rules edge_list patrol_instance vrp_instance ws_command"
    [site]="terrain_asc terrain_geotiff osm_pbf"
    [record]="mcap_replay"
    [missions]="scenario_evacuation scenario_surveillance scenario_demo experiment snapshot"
)
if [ $# -gt 0 ]; then
    targets="$*"
else
    targets=""
    for f in $features; do targets="$targets ${group[$f]}"; done
fi

dev=""
[ "$profile" = dev ] && dev="--dev"
triple=$(rustc -vV | sed -n 's/^host: //p')
# Cargo's dev profile builds into debug/.
outdir=$profile
[ "$profile" = dev ] && outdir=debug
bindir="$CARGO_TARGET_DIR/$triple/$outdir"

# The libFuzzer archive: linked from the cache when there, else built as usual and then kept.
cache=${FUZZ_CACHE:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}}
libfuzzer=""
if [ "$cache" != none ]; then
    version=$(sed -n '/^name = "libfuzzer-sys"$/{n;s/^version = "\(.*\)"$/\1/p}' fuzz/Cargo.lock)
    libfuzzer=$cache/vitro-libfuzzer-$version-$profile/libfuzzer.a
    [ -f "$libfuzzer" ] && export CUSTOM_LIBFUZZER_PATH=$libfuzzer
fi

started=$(date +%s)
if [ "${FUZZ_BUILD:-1}" != 0 ]; then
    (cd fuzz && cargo fuzz build --sanitizer none $dev --no-default-features \
        --features "$(echo $features | tr ' ' ',')")
    if [ -n "$libfuzzer" ] && [ ! -f "$libfuzzer" ]; then
        built_archive=$(ls -t "$bindir"/build/libfuzzer-sys-*/out/libfuzzer.a 2>/dev/null | head -1)
        if [ -n "$built_archive" ]; then
            mkdir -p "$(dirname "$libfuzzer")"
            cp "$built_archive" "$libfuzzer.tmp" && mv "$libfuzzer.tmp" "$libfuzzer"
        fi
    fi
fi
built=$(date +%s)
echo "fuzz build ($profile, features: $features): $((built - started)) s"

# Seeds: repository files matching each target's patterns (git ls-files globs).
seeds() {
    case "$1" in
        pddl_domain | pddl_problem) git ls-files '*.pddl' ;;
        rules) git ls-files '*.jz' ;;
        edge_list) git ls-files '*.edges' ;;
        patrol_instance) git ls-files 'data/patrol/*.toml' ;;
        vrp_instance) git ls-files 'data/vrp/*' ;;
        terrain_asc) git ls-files '*.asc' ;;
        terrain_geotiff) git ls-files '*.tif' '*.tiff' ;;
        osm_pbf) git ls-files '*.pbf' ;;
        scenario_evacuation | scenario_surveillance | scenario_demo)
            git ls-files 'scenarios/*.toml' 'crates/*/tests/*.toml' ;;
        experiment) git ls-files 'experiments/*.toml' ;;
        *) ;;
    esac
}

# Seeds made by the CLI (a recording, a snapshot) when a debug build of it is there.
vitro=${VITRO_BIN:-$repo/target/debug/vitro}
made() {
    local dir=$1 target=$2
    [ -x "$vitro" ] || return 0
    case "$target" in
        mcap_replay)
            "$vitro" run scenarios/demo.toml --until 20 --quiet --record "$dir/demo.mcap" \
                >/dev/null 2>&1 || true ;;
        snapshot)
            "$vitro" run scenarios/demo.toml --until 20 --quiet --save-at 10 \
                --save "$dir/demo.snap" >/dev/null 2>&1 || true ;;
    esac
}

ws_seeds() {
    local dir=$1 i=0
    for c in '{"cmd":"pause"}' '{"cmd":"resume"}' '{"cmd":"step","n":1}' \
        '{"cmd":"speed","factor":2.5}' '{"cmd":"seek","t_ns":5000000000}' \
        '{"cmd":"play"}'; do
        printf '%s' "$c" >"$dir/seed$i.json"
        i=$((i + 1))
    done
}

# One target: seed its corpus, run it, write its table row and whether it failed.
fuzz_one() {
    local t=$1 corpus=$out/corpus/$1 log=$out/$1.log rc=0 execs cov crashes
    mkdir -p "$corpus" "$out/artifacts/$t"
    if [ -z "$(ls -A "$corpus")" ]; then
        seeds "$t" | while read -r f; do
            cp "$f" "$corpus/$(echo "$f" | tr '/' '_')"
        done
        [ "$t" = ws_command ] && ws_seeds "$corpus"
        made "$corpus" "$t"
    fi
    "$bindir/$t" -seed=1 -max_total_time="$seconds" -print_final_stats=1 \
        -rss_limit_mb=4096 -timeout=30 -artifact_prefix="$out/artifacts/$t/" \
        "$corpus" >"$log" 2>&1 || rc=$?
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2 || true)
    # crash-, oom-, timeout- and leak- files; a slow-unit- file is noted, not a failure.
    crashes=$(find "$out/artifacts/$t" -type f ! -name 'slow-unit-*' | wc -l)
    if [ "$rc" -ne 0 ] || [ "$crashes" -gt 0 ]; then
        [ "$crashes" -gt 0 ] || crashes="exit $rc"
        touch "$out/$t.failed"
    fi
    printf '%-22s %8s %12s %8s %8s\n' "$t" "$seconds" "${execs:-?}" "${cov:-?}" "$crashes" \
        >"$out/$t.row"
}

for t in $targets; do
    if [ ! -x "$bindir/$t" ]; then
        echo "no fuzz target binary $bindir/$t (built into another directory?)" >&2
        exit 1
    fi
    rm -f "$out/$t.row" "$out/$t.failed"
done
jobs=${FUZZ_JOBS:-$(nproc)}
for t in $targets; do
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
    fuzz_one "$t" &
done
wait

printf '\n%-22s %8s %12s %8s %8s\n' target seconds executions cov crashes
status=0
for t in $targets; do
    if [ -e "$out/$t.row" ]; then cat "$out/$t.row"; else echo "$t: no result (see $out/$t.log)"; fi
    [ -e "$out/$t.row" ] && [ ! -e "$out/$t.failed" ] || status=1
done
echo "fuzz runs ($jobs at once): $(($(date +%s) - built)) s; corpora, logs and crashes in $out"
exit $status
