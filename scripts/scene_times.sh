#!/usr/bin/env bash
# Run time of the shipped scenes, as the README's table gives it: each scene run as shipped,
#   mpiexec -n P build/fabric -scene inputs/SCENE.yaml -output_every 0
# (the strip also with its frames: scripts/run.sh's command), one after the other, and a table of
# the whole process's wall time beside summary.json's te steps and whether every load step balanced.
#   scripts/scene_times.sh                      every scene but large.yaml (about 4 minutes)
#   scripts/scene_times.sh strip_warp bias@1    the named scenes (@P: on P ranks, else 2;
#                                               strip_warp.yaml or inputs/strip_warp.yaml too)
# Run it on an otherwise idle machine: the times are wall clock.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
scenes=("$@")
[[ ${#scenes[@]} -gt 0 ]] || scenes=(strip_warp strip_weft strip_warp_rupture strip_weft_rupture square_net pushing burst bias
  drape square_1000@1 local_2000@1)
# every entry checked before the first run: scene name and ranks
names=() ranks=()
for entry in "${scenes[@]}"; do
  sc=${entry%@*} np=2
  [[ $entry == *@* ]] && np=${entry##*@}
  # a scene elsewhere (a user's own bias.yaml) is not timed as the shipped one of that name
  if [[ $sc == */* && $(dirname "$sc") != inputs && "$(cd "$(dirname "$sc")" 2>/dev/null && pwd -P)" != "$(cd "$ROOT/inputs" && pwd -P)" ]]; then
    echo "scene_times.sh: scene '$entry': only the scenes of inputs/ (strip_warp, strip_warp.yaml or inputs/strip_warp.yaml)" >&2; exit 2
  fi
  sc=${sc##*/} sc=${sc%.yaml}
  [[ -f $ROOT/inputs/$sc.yaml ]] || { echo "scene_times.sh: scene '$entry': no inputs/$sc.yaml" >&2; exit 2; }
  [[ $np =~ ^[1-9][0-9]*$ ]] || { echo "scene_times.sh: ranks '$np' in '$entry' is not a positive integer" >&2; exit 2; }
  names+=("$sc") ranks+=("$np")
done
source "$ROOT/scripts/setup.sh"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
cd "$ROOT"
printf "%-20s %-6s %5s %9s %10s %9s\n" scene frames ranks wall_s te_steps balanced
run() { # scene, ranks, frames (yes/no), options...
  local scene=$1 np=$2 frames=$3; shift 3
  local t0 t1
  t0=$(date +%s.%N)
  mpiexec -n "$np" build/fabric -scene "inputs/$scene.yaml" -output_dir "$work/$scene" -quiet "$@" >/dev/null
  t1=$(date +%s.%N)
  /usr/bin/python3 - "$work/$scene/summary.json" "$scene" "$frames" "$t0" "$t1" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]:<20} {sys.argv[3]:<6} {s['ranks']:5d} {float(sys.argv[5]) - float(sys.argv[4]):9.2f}"
      f" {s['te_steps']:10d} {'yes' if s['converged'] else 'NO':>9}")
EOF
  rm -rf "${work:?}/$scene"
}
for k in "${!names[@]}"; do
  sc=${names[k]} np=${ranks[k]}
  [[ $sc == strip_warp ]] && run "$sc" "$np" yes
  run "$sc" "$np" no -output_every 0
done
