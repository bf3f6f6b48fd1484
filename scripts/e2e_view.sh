#!/usr/bin/env bash
# End-to-end browser test of `vitro view` (scripts/e2e_view.mjs): installs what it needs
# (Debian chromium, nodejs and npm if missing; npm playwright-core into a scratch directory),
# builds the binary (unless VITRO_BIN names one) and runs the checks. Extra arguments go to the script, e.g.
# `--screenshots docs` to refresh docs/view-2d.png and docs/view-3d.png.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

. scripts/e2e_lib.sh
e2e_setup "chromium node npm" playwright-core@1.56
node scripts/e2e_view.mjs --vitro "$vitro" --modules "$scratch" "$@"
