#!/usr/bin/env bash
# te_table.sh - te against the measured stable limit on shipped scenes (docs/stability.md).
#
#   scripts/te_table.sh [SCENE ...] [-- extra fabric options]
#
# A scene is named as in inputs/ (bias, bias.yaml or inputs/bias.yaml).
# Runs each scene (default: strip_warp strip_weft square_net bias drape pushing) on NP ranks (2) with
# -te_measure set to its number of load steps (the start and end of load step 1 and of the last load
# step are measured), then prints a markdown table from summary.json: the
# te used, the stable bound, the measured limit 2/omega_max and te / limit at the first
# state (load step 1 after its grips moved), the last, the tightest (smallest limit) and the worst
# (largest te / limit), each once. A run that stops gets a "(stopped)" row and the table goes on;
# the script then exits 1.
source "$(dirname "$0")/bench_env.sh" # here, fabric (FABRIC checked, or built), Ctrl-C, positive_ranks
set -euo pipefail
np=${NP:-2}
positive_ranks NP "$np"
scenes=()
while [[ $# -gt 0 && $1 != -- ]]; do
  case $1 in
    -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;;
    -*) echo "te_table.sh: unknown option '$1' (fabric options go after --)" >&2; exit 2 ;;
  esac
  # inputs/bias.yaml from any directory (from another it was refused as not a scene of inputs/)
  if [[ $1 == */* && $(dirname "$1") != inputs && "$(cd "$(dirname "$1")" 2>/dev/null && pwd)" != "$here/inputs" ]]; then
    echo "te_table.sh: scene '$1': only the scenes of inputs/ (bias, bias.yaml or inputs/bias.yaml)" >&2; exit 2
  fi
  sc=$(basename "$1" .yaml)
  [[ -f $here/inputs/$sc.yaml ]] || { echo "te_table.sh: scene '$1': no inputs/$sc.yaml" >&2; exit 2; }
  scenes+=("$sc"); shift
done
[[ ${1:-} == -- ]] && shift
extra=("$@")
[[ ${#scenes[@]} -gt 0 ]] || scenes=(strip_warp strip_weft square_net bias drape pushing)
# -load_steps among the extra options replaces the scene's (the last one given counts)
steps_opt=""
for ((k = 0; k + 1 < ${#extra[@]}; k++)); do [[ ${extra[k]} == -load_steps ]] && steps_opt=${extra[k + 1]}; done
tmp=$(mktemp -d)
stopped=()
trap 'rm -rf "$tmp"' EXIT
echo "| scene | state | te s | stable bound s | measured limit s | te / limit | bound / limit |"
echo "|---|---|---:|---:|---:|---:|---:|"
for sc in "${scenes[@]}"; do
  yaml=$here/inputs/${sc%.yaml}.yaml
  steps=$(sed -n 's/^load_steps: *\([0-9]*\).*/\1/p' "$yaml")
  steps=${steps_opt:-${steps:-50}}
  echo "te_table.sh: $sc ($steps load steps, $np ranks)" >&2
  if ! mpiexec -n "$np" "$fabric" -scene "$yaml" -te_measure "$steps" -output_dir "$tmp/$sc" -output_every 0 -quiet \
    "${extra[@]}" > "$tmp/$sc.log" 2>&1; then
    why=$(grep -m1 'error' "$tmp/$sc.log" || tail -1 "$tmp/$sc.log")
    echo "te_table.sh: $sc stopped: $why" >&2
    echo "| $sc | (stopped) | | | | | |"
    stopped+=("$sc")
    continue
  fi
  /usr/bin/python3 - "$tmp/$sc/summary.json" "$sc" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1])).get("te_measure")
if not s:
    print(f"| {sys.argv[2]} | (not measured) | | | | | |"); sys.exit()
rows = []
for name in ("first", "last", "tightest", "worst"):
    r = s[name]
    if r not in [x for _, x in rows]: rows.append((name, r))
for name, r in rows:
    print(f"| {sys.argv[2]} | {name}: load step {r['load_step']} {r['at']} | {r['te_s']:.3e} | {r['te_bound_s']:.3e} "
          f"| {r['limit_s']:.3e} | {r['te_over_limit']:.3f} | {r['bound_over_limit']:.3f} |")
EOF
done
if ((${#stopped[@]})); then
  echo "te_table.sh: stopped: ${stopped[*]}" >&2; exit 1
fi
