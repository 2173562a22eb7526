#!/usr/bin/env bash
# Grid convergence of the bias extension test: the specimen of verify_bias_extension (60 mm x
# 30 mm, uncrimped yarns, its outline on the grid diagonals) at several thread densities, pulled
# in 4 load steps to 10 % (6 mm): the central shear angle against the kinematic formula
# (MODEL.md 11) at the last step, for glass-like yarns (2600 cN/tex, as the test) and for the
# shirting's 260 cN/tex (yarns 10 times more extensible).
# The default densities keep the grid's specimen at length/width 2 exactly (its outline is
# rounded to the grid diagonals: 15 mm / (spacing / sqrt(2)) = 9, 12, 17, 24).
#   scripts/bias_convergence.sh [threads/cm ...]   (default: 4.243 5.657 8 11.314; NP=ranks, default 1)
set -euo pipefail
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
for n in "$@"; do # each argument a density: it went to fabric as -ends_per_cm, which named it, not the script's argument
  [[ $n =~ ^[0-9]*[.]?[0-9]+$ && ! $n =~ ^[0.]*$ ]] ||
    { echo "bias_convergence.sh: '$n': not a thread density (a number of threads/cm above 0; --help)" >&2; exit 2; }
done
[[ ${NP:-1} =~ ^[1-9][0-9]*$ ]] || { echo "bias_convergence.sh: NP '${NP}': the number of ranks, a positive integer" >&2; exit 2; }
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/setup.sh"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
trap 'echo "bias_convergence.sh: interrupted" >&2; exit 130' INT TERM
densities=("$@"); ((${#densities[@]})) || densities=(4.243 5.657 8 11.314)
printf "%10s %14s %10s %12s %14s %10s %14s %10s\n" threads_cm free_segments travel_mm formula_deg centre_2600 err_2600 centre_260 err_260
for n in "${densities[@]}"; do
  row=()
  for modulus in 2600 260; do
    out="$work/n${n}_m$modulus"
    mpiexec -n "${NP:-1}" "$ROOT/build/fabric" -test bias -gauge_mm 60 -width_mm 30 -ends_per_cm "$n" -picks_per_cm "$n" \
      -warp_crimp_pct 0 -weft_crimp_pct 0 -warp_modulus_cN_tex $modulus -weft_modulus_cN_tex $modulus -gravity 0,0,0 \
      -warp_break_pct 0 -weft_break_pct 0 -shear_lock_deg 35 -elongation_pct 10 -load_steps 4 -predict extrapolate \
      -integrator damped -damping_ratio 0.05 -max_inner_steps 200000 -output_dir "$out" -output_every 0 -quiet >/dev/null
    row+=("$(/usr/bin/python3 - "$out" "$n" <<'PY'
import csv, json, math, sys
out, n = sys.argv[1], float(sys.argv[2])
s = json.load(open(out + "/summary.json"))
r = list(csv.DictReader(open(out + "/curve.csv")))[-1]
D, d, c = s["gauge_mm"] - s["width_mm"], float(r["travel_mm"]), float(r["center_shear_deg"])
g = 90 - 2 * math.degrees(math.acos((D + d) / (math.sqrt(2) * D)))
print(f"{D / (math.sqrt(2) * 10 / n):.0f} {d:.2f} {g:.2f} {c:.2f} {c - g:+.2f} {'balanced' if s['converged'] else 'NOT-balanced'}")
PY
)")
  done
  read -r segs travel formula c1 e1 b1 <<<"${row[0]}"
  read -r _ _ _ c2 e2 b2 <<<"${row[1]}"
  flag=""; [[ $b1 == balanced && $b2 == balanced ]] || flag="  (a load step did not balance: 2600 $b1, 260 $b2)"
  printf "%10s %14s %10s %12s %14s %10s %14s %10s%s\n" "$n" "$segs" "$travel" "$formula" "$c1" "$e1" "$c2" "$e2" "$flag"
done
