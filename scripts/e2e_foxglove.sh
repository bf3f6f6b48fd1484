#!/usr/bin/env bash
# End-to-end test of `vitro view SCENARIO --foxglove` with Foxglove's WebSocket client
# (scripts/e2e_foxglove.mjs): installs what it needs (Debian nodejs and npm if missing; npm
# @foxglove/ws-protocol, @foxglove/schemas, ajv and ws into a scratch directory), builds the binary (unless VITRO_BIN
# names one) and runs the checks. Extra arguments go to the script.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

. scripts/e2e_lib.sh
e2e_setup "node npm" @foxglove/ws-protocol@0.8.0 @foxglove/schemas@2.1.0 ajv@8 ws@8
node scripts/e2e_foxglove.mjs --vitro "$vitro" --modules "$scratch" "$@"
