#!/usr/bin/env bash
# Throughput and scaling: inputs/square_1000.yaml (1000 x 1000 crossings, every force term
# on, a fixed number of te steps) on 1 and 2 ranks, then the roofline row of a te step beside
# what the memory and a plain spring net give on the same grid. Ratios come from one run of
# this script on one machine.
#   scripts/bench.sh [extra fabric options]     (e.g. -max_inner_steps 500)
#
# Table 1: point updates per second per rank (summary.json: the whole run, set-up included)
# and the 2-rank speed-up. Table 2 (1 rank): the te steps alone (the -log_view times of
# FabricForce + FabricIntegrate + FabricHalo + FabricReduce), then build/bench_sweep on the
# same grid: a STREAM-like triad and a plain 4-spring te step (src/bench_sweep.c); last, each
# of those four events per point update (FabricIntegrate holds FIRE's power pass and its exact
# sums besides the update), on 1 rank and on 2 (the slowest rank, per point it updates).
# Bytes and flops per point update are counted from the code (docs/performance.md):
#   bytes: the arrays a te step must stream once per point, 1 rank: force kernel x 24 read,
#     exists + broken_x + broken_y 3, f 24 written; integration f 24, mass 8, inv_m 8, x 24 read
#     + 24 written, v 24 + 24; halo 0 on one rank (Xl reads X's array) = 187 (write-allocate not
#     counted, as STREAM). The spring step: x 24, f 24; f 24, v 48, x 48 = 168.
#   flops: + - * / sqrt of the expressions on an interior point, the yarn law on its linear
#     de-crimping branch: 2 segments x 22, 2 bending centres x 35, 1 shear crossing 65, the
#     gathers 45, the damped update 45 = 269 (compares, selects, max not counted).
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
for a in "$@"; do # the script reads its own profile: a -log_view given would replace it
  [[ ${a,,} != -log_view ]] || { echo "bench.sh: -log_view: the script takes its own profile (Table 2); leave it out" >&2; exit 2; }
done
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
trap 'echo "bench.sh: interrupted" >&2; exit 130' INT TERM
cd "$ROOT"
BYTES=187 FLOPS=269 SPRING_BYTES=168
printf "%-6s %10s %10s %14s %16s %10s\n" ranks points te_steps wall_s "updates/s/rank" speedup
base=""
for np in 1 2; do
  mpiexec -n "$np" build/fabric -scene inputs/square_1000.yaml -output_dir "$work/r$np" -output_every 0 -quiet \
    -log_view ":$work/log$np.txt" "$@" >/dev/null
  read -r points steps wall rate updates < <(/usr/bin/python3 -c "import json; s=json.load(open('$work/r$np/summary.json')); print(s['points'], s['te_steps'], s['wall_s'], s['point_updates_per_s'], s['point_updates'])")
  per_rank=$(/usr/bin/python3 -c "print(f'{$rate/$np:.3e}')")
  [[ -z $base ]] && base=$wall
  speedup=$(/usr/bin/python3 -c "print(f'{$base/$wall:.2f}')")
  printf "%-6s %10s %10s %14.2f %16s %10s\n" "$np" "$points" "$steps" "$wall" "$per_rank" "$speedup"
  [[ $np == 1 ]] && updates1=$updates
done
echo
# the te steps' time on 1 rank, from -log_view (max over ranks, 4th field)
step_s=$(awk '/^Fabric(Force|Integrate|Halo|Reduce) / {t += $4} END {print t}' "$work/log1.txt")
events=$(awk '/^Fabric(Force|Integrate|Halo|Reduce) / {printf "%s=%s ", $1, $4}' "$work/log1.txt")
events2=$(awk '/^Fabric(Force|Integrate|Halo|Reduce) / {printf "%s=%s ", $1, $4}' "$work/log2.txt")
line=$(mpiexec -n 1 build/bench_sweep -scene inputs/square_1000.yaml "$@" -bench_sweeps 20 | tail -n 1)
/usr/bin/python3 - "$updates1" "$step_s" "$line" $BYTES $FLOPS $SPRING_BYTES "$events" "$events2" <<'EOF'
import sys
updates, step_s, line = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
B, F, SB = (float(a) for a in sys.argv[4:7])
ev = dict(w.split("=") for w in sys.argv[7].split())
ev2 = dict(w.split("=") for w in sys.argv[8].split())
kv = dict(w.split("=") for w in line.split())
rate = updates / step_s
spring = float(kv["spring_rate"])
print(f"{'ranks':<6} {'steps_updates/s':>16} {'bytes/upd':>10} {'flops/upd':>10} {'GB/s':>7} {'GFlop/s':>8}"
      f" {'triad_GB/s':>11} {'spring_upd/s':>13} {'spring_GB/s':>12} {'vs_spring':>10}")
print(f"{1:<6} {rate:16.3e} {B:10.0f} {F:10.0f} {rate * B / 1e9:7.2f} {rate * F / 1e9:8.2f}"
      f" {float(kv['triad_GBps']):11.2f} {spring:13.3e} {spring * SB / 1e9:12.2f} {rate / spring:10.2f}")
print(f"bench_sweep, ns per point: halo {kv['halo_ns']}, force kernel {kv['force_ns']}, spring te step {kv['spring_ns']}")
print("te step events (1 rank), ns per point update: " +
      ", ".join(f"{k[6:]} {1e9 * float(ev[k]) / updates:.2f}" for k in
                ("FabricForce", "FabricIntegrate", "FabricHalo", "FabricReduce") if k in ev))
# 2 ranks: each rank updates half the points; the slowest rank's time per point it updates
print("te step events (2 ranks), ns per point update of a rank: " +
      ", ".join(f"{k[6:]} {2e9 * float(ev2[k]) / updates:.2f}" for k in
                ("FabricForce", "FabricIntegrate", "FabricHalo", "FabricReduce") if k in ev2))
EOF
