#!/usr/bin/env bash
# The drape (inputs/drape.yaml, explicit path as shipped) at several thread densities: the same
# 30 cm disc of the same shirting, each grid yarn one real yarn, so the weight per area and the
# bending stiffness per width grow together with the density and the fabric's bending length
# stays (docs/scenes.md, "Grid dependence"). One row per density: the grid, its points in the
# disc, te, the te steps to rest, the wall time and the time a te step takes, and the results
# (drape coefficient, folds, the skirt's drop), and whether the load step balanced.
# Options before the densities go to every run. The runs may take up to -max_inner_steps 3000000 te
# steps (the scene's 300 000 are for 2 threads/cm; the te steps to rest grow with the density).
# usage: scripts/drape_grid.sh [-option value ...] [threads/cm ...]   (default 2 3 4 6)
source "$(dirname "$0")/bench_env.sh"
opts=()
while (($#)) && [[ $1 == -* ]]; do
  (($# >= 2)) || { echo "drape_grid.sh: option $1 without its value (options before the densities are -option value pairs)" >&2; exit 2; }
  opts+=("$1" "$2"); shift 2
done
dens=("$@"); ((${#dens[@]})) || dens=(2 3 4 6)
for d in "${dens[@]}"; do
  [[ $d =~ ^[0-9]+([.][0-9]+)?$ ]] && awk -v d="$d" 'BEGIN{exit !(d > 0)}' ||
    { echo "drape_grid.sh: density '$d': threads/cm, a decimal number above 0 (digits and a point)" >&2; exit 2; }
done
ranks="${RANKS:-2}"
positive_ranks RANKS "$ranks"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
((${#opts[@]})) && echo "options: ${opts[*]}"
printf '%-8s %-9s %8s %10s %10s %9s %10s %7s %6s %8s %9s\n' tpc grid points te_s te_steps wall_s us_per_te dc_pct folds drop_mm balanced
for d in "${dens[@]}"; do
  out="$work/d$d"
  mpiexec -n "$ranks" "$fabric" -scene "$here/inputs/drape.yaml" -ends_per_cm "$d" -picks_per_cm "$d" \
    -max_inner_steps 3000000 -output_every 0 -quiet -output_dir "$out" ${opts[@]+"${opts[@]}"} >"$work/log$d" 2>&1 ||
    { echo "drape_grid.sh: the run at $d threads/cm failed: $(fabric_error "$work/log$d" 3)" >&2; exit 1; }
  s="$out/summary.json"
  grid="$(sed -n 's/.*"grid": \[\([0-9]*\), \([0-9]*\)\].*/\1x\2/p' "$s")"
  te_steps="$(summary_key "$out" te_steps)"; wall="$(summary_key "$out" wall_s)"
  printf '%-8s %-9s %8s %10.3e %10s %9.1f %10.1f %7.2f %6s %8.2f %9s\n' "$d" "$grid" "$(summary_key "$out" points)" "$(summary_key "$out" te_s)" \
    "$te_steps" "$wall" "$(awk -v w="$wall" -v n="$te_steps" 'BEGIN{print (n > 0 ? 1e6 * w / n : 0)}')" \
    "$(summary_key "$out" drape_coefficient_pct)" "$(summary_key "$out" folds)" "$(tail -1 "$out/curve.csv" | cut -d, -f3)" "$(summary_key "$out" converged)"
done
