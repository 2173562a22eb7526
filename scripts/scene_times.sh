#!/usr/bin/env bash
# Run time of the shipped scenes, as the README's table gives it: each scene run as shipped,
#   mpiexec -n P build/fabric -scene inputs/SCENE.yaml -output_every 0
# (the strip also with its frames: scripts/run.sh's command), one after the other, and a table of
# the whole process's wall time beside summary.json's te steps, whether every load step balanced,
# and the scene's result: the drape coefficient, the square net's deflection, else the peak force.
#   scripts/scene_times.sh                      every scene but large.yaml (about 4 minutes)
#   scripts/scene_times.sh strip_warp bias@1    the named scenes (@P: on P ranks, else 2;
#                                               strip_warp.yaml or inputs/strip_warp.yaml too)
#   scripts/scene_times.sh --static [scene ...] each scene also by the quasi-static path
#                                               (-solver static; the drape by TAO's trust region,
#                                               -static_minimizer tao -tao_type ntr -tao_max_it 3000),
#                                               with its Newton and Krylov iterations and its time
#                                               over the explicit run's; by default the lab scenes
#                                               (not the benchmarks square_1000 and local_2000)
# Run it on an otherwise idle machine: the times are wall clock.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
static=no
[[ ${1:-} == --static ]] && { static=yes; shift; }
scenes=("$@")
if [[ ${#scenes[@]} -eq 0 ]]; then
  scenes=(strip_warp strip_weft strip_warp_rupture strip_weft_rupture square_net pushing burst bias drape)
  [[ $static == yes ]] || scenes+=(square_1000@1 local_2000@1)
fi
# every entry checked before the first run: scene name and ranks
names=() ranks=()
for entry in "${scenes[@]}"; do
  [[ $entry != -* ]] || { echo "scene_times.sh: unknown option '$entry' (--static, first, is the only one; --help)" >&2; exit 2; }
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
trap 'echo "scene_times.sh: interrupted" >&2; exit 130' INT TERM
cd "$ROOT"
printf "%-20s %-8s %-6s %5s %9s %10s %7s %7s %9s %10s\n" scene solver frames ranks wall_s te_steps newton krylov balanced result
run() { # scene, ranks, frames (yes/no), options...
  local scene=$1 np=$2 frames=$3; shift 3
  local t0 t1
  t0=$(date +%s.%N)
  mpiexec -n "$np" build/fabric -scene "inputs/$scene.yaml" -output_dir "$work/$scene" -quiet "$@" >/dev/null
  t1=$(date +%s.%N)
  # the explicit run without frames is the one a static run's time is set against
  /usr/bin/python3 - "$work/$scene/summary.json" "$scene" "$frames" "$t0" "$t1" "$work/$scene.explicit_s" <<'EOF'
import json, os, sys
s = json.load(open(sys.argv[1]))
scene, frames, wall, ref = sys.argv[2], sys.argv[3], float(sys.argv[5]) - float(sys.argv[4]), sys.argv[6]
static = s['solver'] == 'static'
its = f"{s['nonlinear_iterations']:7d} {s['linear_iterations']:7d}" if static else f"{'-':>7} {'-':>7}"
test = s['options']['test']
if test == 'drape':
    result = f"{s['drape_coefficient_pct']:.2f} %"
elif test == 'square':  # the loaded crossing's deflection, the last load step's travel
    last = open(os.path.join(os.path.dirname(sys.argv[1]), 'curve.csv')).read().split()[-1].split(',')
    result = f"{float(last[2]):.5g} mm"
else:
    result = f"{s['peak_force_N']:.5g} N"
ratio = f"  ({wall / float(open(ref).read()):.2f} x explicit)" if static and os.path.exists(ref) else ""
if not static and frames == 'no':
    open(ref, 'w').write(f"{wall:.6f}")
te = f"{s['te_steps']:10d}" if not static else f"{'-':>10}"  # the static path takes no te step
print(f"{scene:<20} {s['solver']:<8} {frames:<6} {s['ranks']:5d} {wall:9.2f} {te} {its}"
      f" {'yes' if s['converged'] else 'NO':>9} {result:>10}{ratio}")
EOF
  rm -rf "${work:?}/$scene"
}
for k in "${!names[@]}"; do
  sc=${names[k]} np=${ranks[k]}
  [[ $sc == strip_warp ]] && run "$sc" "$np" yes
  run "$sc" "$np" no -output_every 0
  if [[ $static == yes ]]; then
    tao=()
    [[ $sc == drape ]] && tao=(-static_minimizer tao -tao_type ntr -tao_max_it 3000)
    run "$sc" "$np" no -output_every 0 -solver static ${tao[@]+"${tao[@]}"}
  fi
done
