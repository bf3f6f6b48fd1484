#!/usr/bin/env bash
# The pursuit theory table: on every reference graph (data/graphs, cop number c stated on the
# first line), c-1 and c pursuers with full visibility against the exact evader; capture rate
# with its 95% interval, as a Markdown table (the table only: the command states its
# arguments; --turns 30 --seed 1 always).
# Usage: scripts/pursuit_table.sh [VITRO] [ALGORITHM] [BUDGET] [EPISODES]
set -euo pipefail
vitro=${1:-target/release/vitro}
algorithm=${2:-mcts}
budget=${3:-300}
episodes=${4:-20}
turns=30
seed=1
echo "| graph | cop number | pursuers | capture rate | 95% CI | mean capture turn |"
echo "|---|---|---|---|---|---|"
for f in data/graphs/*.edges; do
  c=$(head -1 "$f" | sed 's/.*cop number *//')
  for k in $((c - 1)) "$c"; do
    [ "$k" -ge 1 ] || continue
    "$vitro" solve pursuit "$f" --pursuers "$k" --algorithm "$algorithm" --budget "$budget" \
      --episodes "$episodes" --turns "$turns" --seed "$seed" --json |
      python3 -c '
import json, sys
r = json.load(sys.stdin)
t = "-" if r["mean_capture_turn"] is None else "%.1f" % r["mean_capture_turn"]
lo, hi = r["capture_rate_ci95"]
print("| %s | %s | %d | %.2f | %.2f-%.2f | %s |" % (sys.argv[1], sys.argv[2], r["pursuers"], r["capture_rate"], lo, hi, t))
' "$(basename "$f" .edges)" "$c"
  done
done
