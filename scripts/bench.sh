#!/usr/bin/env bash
# Throughput and scaling: inputs/square_1000.yaml (1000 x 1000 crossings, every force term
# on, a fixed number of te steps) on 1 and 2 ranks. Prints point updates per second per
# rank and the 2-rank speed-up. Ratios come from one run of this script on one machine.
#   scripts/bench.sh [extra fabric options]     (e.g. -max_inner_steps 500)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
cd "$ROOT"
printf "%-6s %10s %10s %14s %16s %10s\n" ranks points te_steps wall_s "updates/s/rank" speedup
base=""
for np in 1 2; do
  mpiexec -n "$np" build/fabric -scene inputs/square_1000.yaml -output_dir "$work/r$np" -output_every 0 -quiet "$@" >/dev/null
  read -r points steps wall rate < <(/usr/bin/python3 -c "import json,sys; s=json.load(open('$work/r$np/summary.json')); print(s['points'], s['te_steps'], s['wall_s'], s['point_updates_per_s'])")
  per_rank=$(/usr/bin/python3 -c "print(f'{$rate/$np:.3e}')")
  [[ -z $base ]] && base=$wall
  speedup=$(/usr/bin/python3 -c "print(f'{$base/$wall:.2f}')")
  printf "%-6s %10s %10s %14.2f %16s %10s\n" "$np" "$points" "$steps" "$wall" "$per_rank" "$speedup"
done
