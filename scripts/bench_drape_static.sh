#!/usr/bin/env bash
# The drape (inputs/drape.yaml, 2 threads/cm, one load step) by the quasi-static path, in one run of
# this script: SNES and TAO's trust region, the tangent's compressed segments by the tension field
# throughout (-static_exact_tangent 0), exact near balance (the default 0.1) or exact throughout
# (1e9), by multigrid or LU. Each row: its ranks and options, whether the load step balanced, its
# Newton and Krylov iterations, wall time, drape coefficient and folds.
# usage: scripts/bench_drape_static.sh [extra options for every run, e.g. -contact_stiffness_N_m 200]
source "$(dirname "$0")/bench_env.sh"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
extra=("$@")

snes="-snes_max_it 1000"
lu="-snes_max_it 1000 -static_tangent aij -pc_type lu"
tao="-static_minimizer tao -tao_type ntr -tao_max_it 3000"
# ranks|options
runs=("1|$snes" "1|$snes -static_exact_tangent 0" "1|$snes -static_exact_tangent 1e9"
      "2|$snes" "2|$snes -static_exact_tangent 0" "2|$snes -static_exact_tangent 1e9"
      "1|$lu" "1|$lu -static_exact_tangent 0"
      "1|$tao" "1|$tao -static_exact_tangent 0")

((${#extra[@]})) && echo "options of every run, after the row's (they win): ${extra[*]}"
printf '%5s %-70s %8s %7s %8s %8s %7s %5s\n' ranks options balanced newton krylov wall_s DC_pct folds
k=0
for r in "${runs[@]}"; do
  k=$((k + 1))
  n="${r%%|*}" opts="${r#*|}"
  # shellcheck disable=SC2086
  mpiexec -n "$n" "$fabric" -scene "$here/inputs/drape.yaml" -solver static -output_every 0 -quiet \
    -output_dir "$work/$k" $opts "${extra[@]}" >"$work/$k.log" 2>&1 || {
    echo "bench_drape_static.sh: run $k ($opts) failed: $(fabric_error "$work/$k.log")" >&2
    exit 1
  }
  printf '%5s %-70s %8s %7s %8s %8.1f %7s %5s\n' "$n" "$opts" "$(summary_key "$work/$k" converged)" "$(summary_key "$work/$k" nonlinear_iterations)" \
    "$(summary_key "$work/$k" linear_iterations)" "$(summary_key "$work/$k" wall_s)" "$(summary_key "$work/$k" drape_coefficient_pct)" "$(summary_key "$work/$k" folds)"
done
