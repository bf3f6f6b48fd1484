#!/usr/bin/env bash
# End-to-end browser test of `vitro view` (scripts/e2e_view.mjs): installs what it needs
# (Debian chromium, nodejs and npm if missing; npm playwright-core into a scratch directory),
# builds the binary (unless VITRO_BIN names one) and runs the checks. Extra arguments go to the script, e.g.
# `--screenshots docs` to refresh docs/view-2d.png and docs/view-3d.png.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

need=()
command -v chromium >/dev/null || need+=(chromium)
command -v node >/dev/null || need+=(nodejs)
command -v npm >/dev/null || need+=(npm)
if ((${#need[@]})); then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
(cd "$scratch" && npm init -y >/dev/null && npm install --silent --no-audit --no-fund playwright-core@1.56)

# VITRO_BIN: a vitro binary already built (CI passes the one `cargo test` made).
vitro="${VITRO_BIN:-}"
if [[ -z "$vitro" ]]; then
  cargo build -q -p vitro-cli
  vitro="${CARGO_TARGET_DIR:-target}/debug/vitro"
fi
node scripts/e2e_view.mjs --vitro "$vitro" --modules "$scratch" "$@"
