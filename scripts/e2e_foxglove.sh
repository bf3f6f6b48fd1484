#!/usr/bin/env bash
# End-to-end test of `vitro view SCENARIO --foxglove` with Foxglove's WebSocket client
# (scripts/e2e_foxglove.mjs): installs what it needs (Debian nodejs and npm if missing; npm
# @foxglove/ws-protocol, @foxglove/schemas, ajv and ws into a scratch directory), builds the binary (unless VITRO_BIN
# names one) and runs the checks. Extra arguments go to the script.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

need=()
command -v node >/dev/null || need+=(nodejs)
command -v npm >/dev/null || need+=(npm)
if ((${#need[@]})); then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
(cd "$scratch" && npm init -y >/dev/null &&
  npm install --silent --no-audit --no-fund @foxglove/ws-protocol@0.8.0 @foxglove/schemas@2.1.0 ajv@8 ws@8)

# VITRO_BIN: a vitro binary already built (CI passes the one `cargo test` made).
vitro="${VITRO_BIN:-}"
if [[ -z "$vitro" ]]; then
  cargo build -q -p vitro-cli
  vitro="${CARGO_TARGET_DIR:-target}/debug/vitro"
fi
node scripts/e2e_foxglove.mjs --vitro "$vitro" --modules "$scratch" "$@"
